#pragma once
// Synthetic IMU from a trajectory's exact derivatives, with the Kalibr/EuRoC noise model:
//   gyro  = omega_B + b_g + n_g
//   accel = R_W_B^T (a_W - g_W) + b_a + n_a,   g_W = (0, 0, -9.81)
// Continuous-time densities become discrete per sample as sigma_d = density / sqrt(dt); biases
// random-walk with sigma = random_walk * sqrt(dt) per sample.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "data/sim/sim_trajectory.h"
#include "data/types.h"

namespace adugs::data {

constexpr double kSimGravity = 9.81;

struct SimImuOptions {
  double rate_hz = 200.0;
  // EuRoC ADIS16448 figures (imu0/sensor.yaml).
  double gyro_noise_density = 1.6968e-04;   // rad / s / sqrt(Hz)
  double gyro_random_walk = 1.9393e-05;     // rad / s^2 / sqrt(Hz)
  double accel_noise_density = 2.0000e-3;   // m / s^2 / sqrt(Hz)
  double accel_random_walk = 3.0000e-3;     // m / s^3 / sqrt(Hz)
  bool noise = true;                        // false: exact measurements (biases stay constant)
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();
  uint64_t seed = 0;
};

// One IMU sample plus the true state it was generated from (for the ground-truth file).
struct SimImuRecord {
  ImuSample sample;
  SimBodyState truth;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
};

// Noise-free specific force and body rate of one state.
ImuSample idealImu(const SimBodyState& state);

// Samples at start + k * period for every k with t <= end. Deterministic in options.seed.
std::vector<SimImuRecord> synthesizeImu(const SimTrajectory& trajectory,
                                        const SimImuOptions& options);

}  // namespace adugs::data

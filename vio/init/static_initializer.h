#pragma once
// Static initialization: when the platform stands still (IMU quiet and the image features do not
// move), gravity and the gyro bias are observable from the IMU alone. The body orientation is the
// rotation that maps the mean specific force onto +z (at rest it is -g = +9.81 z), with zero yaw
// (yaw is unobservable without motion; the world frame takes the body's heading).
//
// "Quiet" is judged on block means of the IMU over `smoothing_s` (0.1 s): a flying platform's
// rotors shake the IMU at high frequency, aliased into the 200 Hz samples (EuRoC V1_01 at rest
// on the ground with the motors on: per-sample accel std ~1 m/s^2, more than in flight), while real
// motion lives at low frequency. Thresholds tuned on the real V1_01 IMU, see doc/estimator.md.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "data/types.h"

namespace adugs::vio {

struct StaticInitOptions {
  double window_s = 1.0;         // IMU span inspected
  double max_accel_std = 0.25;   // m/s^2, per axis std of the smoothed specific force
  double max_gyro_std = 0.016;   // rad/s, per axis std of the smoothed rate
  double max_parallax_px = 1.0;  // mean feature motion over the window, pixels
  double smoothing_s = 0.1;      // block length for the means whose std is tested (0: raw samples)
  double max_gravity_norm_error = 0.5;  // m/s^2: | |mean accel| - 9.81 | above this = not at rest
  int min_samples = 20;                 // fewer IMU samples in the window = cannot decide
};

struct StaticInitResult {
  bool stationary = false;
  std::string reason;                                         // why not stationary
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();  // gravity-aligned (z up), yaw = 0
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();        // mean gyro over the window
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // unobservable from one static pose: zero
  Eigen::Vector3d mean_accel = Eigen::Vector3d::Zero();
  Eigen::Vector3d smoothed_gyro_std = Eigen::Vector3d::Zero();  // what was compared, per axis
  Eigen::Vector3d smoothed_accel_std = Eigen::Vector3d::Zero();
};

// imu_window: the samples of the last window_s seconds (time-ordered); mean_parallax_px: mean
// feature displacement between the first and last frame of that window (pixels). Never throws;
// non-finite input or a too short window gives stationary = false with a reason.
StaticInitResult initializeStatic(const std::vector<data::ImuSample>& imu_window,
                                  double mean_parallax_px, const StaticInitOptions& options = {});

// R_W_B with R_W_B * specific_force along +z and zero ZYX yaw. `specific_force` must be non-zero.
Eigen::Quaterniond gravityAlignedOrientation(const Eigen::Vector3d& specific_force);

// The ZYX yaw of R removed: Rz(-yaw(R)) * R.
Eigen::Matrix3d removeYaw(const Eigen::Matrix3d& R);

}  // namespace adugs::vio

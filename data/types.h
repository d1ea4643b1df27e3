#pragma once
// Plain measurement and pose types shared by every module. Time is int64 nanoseconds.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace adugs::data {

inline double nsToSec(int64_t t_ns) { return static_cast<double>(t_ns) * 1e-9; }
inline int64_t secToNs(double t_s) { return static_cast<int64_t>(t_s * 1e9 + (t_s >= 0 ? 0.5 : -0.5)); }

// One IMU reading in the IMU (body) frame B: angular rate [rad/s], specific force [m/s^2].
struct ImuSample {
  int64_t t_ns = 0;
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

// A pose T_W_B at time t: p_W = q_W_B * p_B + p_W_B.
struct StampedPose {
  int64_t t_ns = 0;
  Eigen::Vector3d p_W_B = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Full ground-truth state as in EuRoC's state_groundtruth_estimate0 (velocity and biases optional).
struct GroundTruthState {
  StampedPose pose;
  bool has_velocity_and_biases = false;
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
};

}  // namespace adugs::data

#pragma once
// Strapdown propagation of a navigation state with IMU samples (midpoint rule, as VINS-Mono's
// preintegration uses), the building block of IMU preintegration and of IMU-only dead reckoning.
//   a_W = R_W_B (f_B - b_a) + g_W,   dR/dt = R [omega_B - b_g]x
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "data/types.h"
#include "vio/imu/so3.h"  // quaternionExp

namespace adugs::vio {

struct NavState {
  int64_t t_ns = 0;
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_W_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
};

// Gravity in the world frame (z up), m/s^2.
inline Eigen::Vector3d gravityWorld() { return {0.0, 0.0, -9.81}; }

// Propagates `state` (valid at sample a's time) to sample b's time with the midpoint of a and b.
// Throws std::invalid_argument if b is not after a.
NavState propagateMidpoint(const NavState& state, const data::ImuSample& a,
                           const data::ImuSample& b, const Eigen::Vector3d& g_W = gravityWorld());

}  // namespace adugs::vio

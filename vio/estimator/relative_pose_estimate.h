#pragma once
// What the estimator believes about the newest frame's pose relative to the oldest window frame,
// with the window's covariance of it: the input of the consistency check (vio/eval/consistency.h).
// The relative pose is free of the unobservable heading and position, so the covariance is the
// window's own (its information conditioned on the oldest pose), whatever holds the gauge.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace adugs::vio {

struct RelativePoseEstimate {
  int64_t t_from_ns = 0, t_to_ns = 0;  // IMU times of the oldest and the newest window frame
  // T_from_to: the newest body frame in the oldest one.
  Eigen::Vector3d p_from_to = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_from_to = Eigen::Quaterniond::Identity();
  // Of the error [dp (in the oldest body frame), dtheta (rotation perturbed on the right, in the
  // newest body frame)]: estimate = truth (+) error.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
};

}  // namespace adugs::vio

#pragma once
// Body (or camera) rotation between two frame times from the gyro alone (midpoint rule), for the
// tracker's KLT prediction and the masker's camera-motion compensation. The front-end runs ahead
// of the estimator on its own thread, so it keeps its own short IMU buffer and takes the gyro bias
// (the estimator's, a frame or two old) as input.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>

#include "data/types.h"

namespace adugs::vio {

class GyroRotationPredictor {
 public:
  // Samples must come in increasing time (the reader guarantees it).
  void addImu(const data::ImuSample& sample);

  // R_B(from)_B(to): integrates (omega - gyro_bias) from from_ns to to_ns, with the rates at the
  // two ends interpolated between samples (held constant beyond the buffer). Identity when the
  // buffer is empty or to_ns <= from_ns.
  Eigen::Quaterniond rotation(int64_t from_ns, int64_t to_ns,
                              const Eigen::Vector3d& gyro_bias) const;

  // The same rotation seen by a camera mounted with rotation R_B_C (camera to body):
  // R_C(from)_C(to) = R_B_C^T R_B(from)_B(to) R_B_C.
  Eigen::Matrix3d cameraRotation(int64_t from_ns, int64_t to_ns, const Eigen::Vector3d& gyro_bias,
                                 const Eigen::Matrix3d& R_B_C) const {
    return R_B_C.transpose() * rotation(from_ns, to_ns, gyro_bias).toRotationMatrix() * R_B_C;
  }

  // Forgets samples no longer needed for intervals starting at or after t_ns.
  void dropBefore(int64_t t_ns);

  size_t size() const { return samples_.size(); }

 private:
  Eigen::Vector3d rateAt(int64_t t_ns) const;
  std::deque<data::ImuSample> samples_;
};

}  // namespace adugs::vio

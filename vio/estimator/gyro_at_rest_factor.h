#pragma once
// At rest the gyroscope measures its own bias: for a frame detected as stationary,
// r = (bg - mean gyro over the frame's IMU interval) / sigma, per axis, on the speed-bias block
// [v(3), ba(3), bg(3)]. The zero-velocity factor alone leaves the gyro bias about gravity (the
// yaw rate) free while the landmarks have no depth: on a hybrid V1_01 start it drifted from 0.002
// to 0.44 rad/s in 3 s of standstill, taking the accelerometer bias along (doc/estimator.md).
#include <vector>

#include <Eigen/Core>
#include <ceres/sized_cost_function.h>

namespace adugs::vio {

class GyroAtRestFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  GyroAtRestFactor(const Eigen::Vector3d& mean_gyro, const Eigen::Vector3d& sigma)
      : mean_gyro_(mean_gyro), inv_sigma_(sigma.cwiseInverse()) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (int k = 0; k < 3; ++k) residuals[k] = (parameters[0][6 + k] - mean_gyro_[k]) * inv_sigma_[k];
    if (jacobians && jacobians[0]) {
      for (int k = 0; k < 27; ++k) jacobians[0][k] = 0;  // 3 x 9, row-major
      for (int k = 0; k < 3; ++k) jacobians[0][k * 9 + 6 + k] = inv_sigma_[k];
    }
    return true;
  }

 private:
  Eigen::Vector3d mean_gyro_;
  Eigen::Vector3d inv_sigma_;
};

// The mean gyro rate over `samples` and its standard error per axis: the samples' own spread
// (rotor vibration) or the sensor's white noise (density * sqrt(rate)), whichever is larger,
// over sqrt(n). False with fewer than 2 samples.
bool gyroMeanAtRest(const std::vector<Eigen::Vector3d>& rates, double rate_hz, double gyro_noise_density,
                    Eigen::Vector3d* mean, Eigen::Vector3d* sigma);

}  // namespace adugs::vio

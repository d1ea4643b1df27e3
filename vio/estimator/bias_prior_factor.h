#pragma once
// A prior on one bias of a speed-bias block [v(3), ba(3), bg(3)]: r = (b - mean) / sigma per axis.
// Two uses, both while standing still, where the landmarks have no depth and the window holds
// its state with the IMU, the zero-velocity factors (velocity only) and its prior:
// - gyro at rest: a stationary frame's gyro measures its own bias (mean rate over the frame's IMU
//   interval). Without it the bias about gravity (the yaw rate) is free: on a hybrid V1_01 start
//   it drifted from 0.002 to 0.44 rad/s in 3 s of standstill.
// - accelerometer at a static initialisation: at rest the tilt and the horizontal accelerometer
//   bias are one unknown (gravity is measured as their sum), so the window can tilt as a whole
//   with the bias following; on a simulated TUM-VI fisheye start it tilted 15 deg in 0.5 s and
//   the bias passed its 2.5 m/s^2 limit. The initialisation's bias, held with a sigma as
//   OpenVINS' static initialiser's covariance does, removes that freedom (doc/estimator.md).
#include <vector>

#include <Eigen/Core>
#include <ceres/sized_cost_function.h>

namespace adugs::vio {

class BiasPriorFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  enum class Bias { kAccel = 3, kGyro = 6 };  // offset in the speed-bias block
  BiasPriorFactor(Bias bias, const Eigen::Vector3d& mean, const Eigen::Vector3d& sigma)
      : offset_(static_cast<int>(bias)), mean_(mean), inv_sigma_(sigma.cwiseInverse()) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (int k = 0; k < 3; ++k) residuals[k] = (parameters[0][offset_ + k] - mean_[k]) * inv_sigma_[k];
    if (jacobians && jacobians[0]) {
      for (int k = 0; k < 27; ++k) jacobians[0][k] = 0;  // 3 x 9, row-major
      for (int k = 0; k < 3; ++k) jacobians[0][k * 9 + offset_ + k] = inv_sigma_[k];
    }
    return true;
  }

 private:
  int offset_;
  Eigen::Vector3d mean_;
  Eigen::Vector3d inv_sigma_;
};

// The mean gyro rate over `samples` and its standard error per axis: the samples' own spread
// (rotor vibration) or the sensor's white noise (density * sqrt(rate)), whichever is larger,
// over sqrt(n). False with fewer than 2 samples.
bool gyroMeanAtRest(const std::vector<Eigen::Vector3d>& rates, double rate_hz, double gyro_noise_density,
                    Eigen::Vector3d* mean, Eigen::Vector3d* sigma);

}  // namespace adugs::vio

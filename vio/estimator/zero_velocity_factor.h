#pragma once
// Zero-velocity update (ZUPT) for a frame detected as stationary (quiet IMU, no image motion):
// r = v_W / sigma on the speed-bias block [v(3), ba(3), bg(3)]. A monocular estimator that stands
// still has no parallax, so its landmarks have no depth; this keeps the velocity, and with it
// the position, from drifting on IMU integration alone.
#include <ceres/sized_cost_function.h>

namespace adugs::vio {

class ZeroVelocityFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  explicit ZeroVelocityFactor(double sigma_mps) : inv_sigma_(1.0 / sigma_mps) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (int k = 0; k < 3; ++k) residuals[k] = parameters[0][k] * inv_sigma_;
    if (jacobians && jacobians[0]) {
      for (int k = 0; k < 27; ++k) jacobians[0][k] = 0;  // 3 x 9, row-major
      for (int k = 0; k < 3; ++k) jacobians[0][k * 9 + k] = inv_sigma_;
    }
    return true;
  }

 private:
  double inv_sigma_;
};

}  // namespace adugs::vio

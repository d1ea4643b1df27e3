#pragma once
// Gaussian prior on a one-value block (the camera-IMU time offset): r = (x - x0) / sigma.
// It keeps a weakly observed scalar near its calibrated value; like the extrinsic prior it is
// added to every window solve and not marginalised (so it does not accumulate).
#include <ceres/sized_cost_function.h>

namespace adugs::vio {

class ScalarPriorFactor : public ceres::SizedCostFunction<1, 1> {
 public:
  ScalarPriorFactor(double x0, double sigma) : x0_(x0), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = (parameters[0][0] - x0_) * inv_sigma_;
    if (jacobians && jacobians[0]) jacobians[0][0] = inv_sigma_;
    return true;
  }

 private:
  double x0_, inv_sigma_;
};

}  // namespace adugs::vio

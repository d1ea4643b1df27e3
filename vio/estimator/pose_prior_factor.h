#pragma once
// A Gaussian prior on a pose block [p, q x y z w] (PoseManifold):
//   r = [ (p - p0) / sigma_p ; Log(q0^-1 q) / sigma_theta ].
// Holds the online camera-IMU extrinsic near its calibrated value while the window's motion does
// not make it observable (VINS-Mono leaves it free and relies on excitation; a weak prior keeps
// a short or rotation-poor window from dragging it away).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vio/estimator/tangent_cost_function.h"

namespace adugs::vio {

class PosePriorFactor : public TangentCostFunction {
 public:
  PosePriorFactor(const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0, double sigma_p_m,
                  double sigma_theta_rad);
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** jacobians) const override;

 private:
  Eigen::Vector3d p0_;
  Eigen::Quaterniond q0_;
  double inv_sigma_p_, inv_sigma_theta_;
};

}  // namespace adugs::vio

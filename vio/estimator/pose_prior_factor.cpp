#include "vio/estimator/pose_prior_factor.h"

#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {

PosePriorFactor::PosePriorFactor(const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0,
                                 double sigma_p_m, double sigma_theta_rad)
    : TangentCostFunction(6, {kPoseSize}),
      p0_(p0),
      q0_(q0.normalized()),
      inv_sigma_p_(1.0 / sigma_p_m),
      inv_sigma_theta_(1.0 / sigma_theta_rad) {}

bool PosePriorFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                      double** jacobians) const {
  const Eigen::Vector3d p = posePosition(parameters[0]);
  const Eigen::Quaterniond q = poseRotation(parameters[0]);
  const Eigen::Vector3d phi = quaternionLog(q0_.conjugate() * q);
  Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
  r.head<3>() = inv_sigma_p_ * (p - p0_);
  r.tail<3>() = inv_sigma_theta_ * phi;
  if (jacobians && jacobians[0]) {
    // Right perturbation q Exp(d): Log(q0^-1 q Exp(d)) ~ phi + Jr^-1(phi) d.
    Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
    J.topLeftCorner<3, 3>() = inv_sigma_p_ * Eigen::Matrix3d::Identity();
    J.bottomRightCorner<3, 3>() = inv_sigma_theta_ * rightJacobianInverse(phi);
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J_out(jacobians[0]);
    J_out = J;
  }
  return true;
}

}  // namespace adugs::vio

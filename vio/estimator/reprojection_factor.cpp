#include "vio/estimator/reprojection_factor.h"

#include <Eigen/Geometry>

#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {

namespace {

// Residual and tangent Jacobians shared by both factors. jacobians[0..3]: pose_i, pose_j, T_B_C
// (2 x 6 row-major, [dp, dtheta]), lambda (2 x 1).
// d_pt_i (optional): d r / d pt_i (2x2), for the time-offset chain rule.
void evaluateTwoFrame(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j, double s,
                      double const* const* parameters, double* residuals, double** jacobians,
                      Eigen::Matrix2d* d_pt_i) {
  const Eigen::Vector3d P_i = posePosition(parameters[0]), P_j = posePosition(parameters[1]);
  const Eigen::Vector3d t_ic = posePosition(parameters[2]);
  const Eigen::Quaterniond q_i = poseRotation(parameters[0]), q_j = poseRotation(parameters[1]);
  const Eigen::Quaterniond q_ic = poseRotation(parameters[2]);
  const double lambda = parameters[3][0];

  const Eigen::Vector3d f_i(pt_i.x(), pt_i.y(), 1.0);
  const Eigen::Vector3d p_ci = f_i / lambda;
  const Eigen::Vector3d p_bi = q_ic * p_ci + t_ic;
  const Eigen::Vector3d p_w = q_i * p_bi + P_i;
  const Eigen::Vector3d p_bj = q_j.conjugate() * (p_w - P_j);
  const Eigen::Vector3d p_cj = q_ic.conjugate() * (p_bj - t_ic);
  const double z = p_cj.z();
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = s * (p_cj.head<2>() / z - pt_j);
  if (!jacobians && !d_pt_i) return;

  Eigen::Matrix<double, 2, 3> J_proj;
  J_proj << 1.0 / z, 0.0, -p_cj.x() / (z * z), 0.0, 1.0 / z, -p_cj.y() / (z * z);
  J_proj *= s;
  // The chain rule with the 2 x 3 projection Jacobian applied first: every term below is a
  // 2 x 3 times 3 x 3 product (not 3 x 3 times 3 x 3, then 2 x 3 times 3 x 6).
  const Eigen::Matrix3d R_i = q_i.toRotationMatrix(), R_ic = q_ic.toRotationMatrix();
  const Eigen::Matrix<double, 2, 3> A = J_proj * R_ic.transpose();      // d r / d p_bj
  const Eigen::Matrix<double, 2, 3> B = A * q_j.conjugate().toRotationMatrix();  // d r / d p_w
  const Eigen::Matrix<double, 2, 3> B_i = B * R_i;                      // d r / d p_bi
  const Eigen::Matrix<double, 2, 3> C = B_i * R_ic;                     // d r / d p_ci

  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_out(jacobians[0]);
    J_out.leftCols<3>() = B;
    J_out.rightCols<3>() = -B_i * skew(p_bi);
  }
  if (jacobians && jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_out(jacobians[1]);
    J_out.leftCols<3>() = -B;
    J_out.rightCols<3>() = A * skew(p_bj);
  }
  if (jacobians && jacobians[2]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_out(jacobians[2]);
    J_out.leftCols<3>() = B_i - A;
    J_out.rightCols<3>() = J_proj * skew(p_cj) - C * skew(p_ci);
  }
  if (jacobians && jacobians[3]) {
    Eigen::Map<Eigen::Vector2d> J_out(jacobians[3]);
    J_out = C * f_i * (-1.0 / (lambda * lambda));
  }
  if (d_pt_i) *d_pt_i = C.leftCols<2>() / lambda;
}

}  // namespace

ReprojectionFactor::ReprojectionFactor(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                                       double sqrt_information)
    : TangentCostFunction(2, {kPoseSize, kPoseSize, kPoseSize, 1}) {
  setMeasurement(pt_i, pt_j, sqrt_information);
}

void ReprojectionFactor::setMeasurement(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                                        double sqrt_information) {
  pt_i_ = pt_i;
  pt_j_ = pt_j;
  sqrt_information_ = sqrt_information;
}

bool ReprojectionFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  evaluateTwoFrame(pt_i_, pt_j_, sqrt_information_, parameters, residuals, jacobians, nullptr);
  return true;
}

ReprojectionTdFactor::ReprojectionTdFactor(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                                           const Eigen::Vector2d& vel_i,
                                           const Eigen::Vector2d& vel_j, double td_i, double td_j,
                                           double sqrt_information)
    : TangentCostFunction(2, {kPoseSize, kPoseSize, kPoseSize, 1, 1}) {
  setMeasurement(pt_i, pt_j, vel_i, vel_j, td_i, td_j, sqrt_information);
}

void ReprojectionTdFactor::setMeasurement(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                                          const Eigen::Vector2d& vel_i,
                                          const Eigen::Vector2d& vel_j, double td_i, double td_j,
                                          double sqrt_information) {
  pt_i_ = pt_i;
  pt_j_ = pt_j;
  vel_i_ = vel_i;
  vel_j_ = vel_j;
  td_i_ = td_i;
  td_j_ = td_j;
  sqrt_information_ = sqrt_information;
}

bool ReprojectionTdFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                           double** jacobians) const {
  const double td = parameters[4][0];
  const Eigen::Vector2d pt_i = pt_i_ - (td - td_i_) * vel_i_;
  const Eigen::Vector2d pt_j = pt_j_ - (td - td_j_) * vel_j_;
  const bool want_td = jacobians && jacobians[4];
  Eigen::Matrix2d d_pt_i;
  evaluateTwoFrame(pt_i, pt_j, sqrt_information_, parameters, residuals, jacobians,
                   want_td ? &d_pt_i : nullptr);
  if (want_td) {
    Eigen::Map<Eigen::Vector2d> J_out(jacobians[4]);
    J_out = -d_pt_i * vel_i_ + sqrt_information_ * vel_j_;
  }
  return true;
}

}  // namespace adugs::vio

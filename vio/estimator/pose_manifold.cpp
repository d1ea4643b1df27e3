#include "vio/estimator/pose_manifold.h"

#include "vio/imu/so3.h"

namespace adugs::vio {

Eigen::Matrix<double, 3, 4> quaternionLiftJacobian(const Eigen::Quaterniond& q) {
  // dtheta = 2 vec(q^* (q + dq)) to first order = 2 (w dv - dw v - v x dv).
  Eigen::Matrix<double, 3, 4> M;
  M.leftCols<3>() = 2.0 * (q.w() * Eigen::Matrix3d::Identity() - skew(q.vec()));
  M.col(3) = -2.0 * q.vec();
  return M;
}

Eigen::Matrix<double, 4, 3> quaternionPlusJacobian(const Eigen::Quaterniond& q) {
  // q * (1, dtheta / 2): vec part 0.5 (w I + [v]x) dtheta, scalar part -0.5 v . dtheta.
  Eigen::Matrix<double, 4, 3> P;
  P.topRows<3>() = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + skew(q.vec()));
  P.row(3) = -0.5 * q.vec().transpose();
  return P;
}

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Map<const Eigen::Vector3d> dp(delta), dtheta(delta + 3);
  Eigen::Map<Eigen::Vector3d> p_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  p_out = posePosition(x) + dp;
  q_out = (poseRotation(x) * quaternionExp(dtheta)).normalized();
  return true;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<4, 3>() = quaternionPlusJacobian(Eigen::Quaterniond(poseRotation(x)));
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Eigen::Vector3d> dp(y_minus_x), dtheta(y_minus_x + 3);
  dp = posePosition(y) - posePosition(x);
  dtheta = quaternionLog(poseRotation(x).conjugate() * poseRotation(y));
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<3, 4>() = quaternionLiftJacobian(Eigen::Quaterniond(poseRotation(x)));
  return true;
}

void setPose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double* x) {
  Eigen::Map<Eigen::Vector3d> p_out(x);
  Eigen::Map<Eigen::Quaterniond> q_out(x + 3);
  p_out = p;
  q_out = q.normalized();
}

}  // namespace adugs::vio

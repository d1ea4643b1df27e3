#include "vio/imu/so3.h"

#include <cmath>

namespace adugs::vio {

namespace {
// Below this angle the series expansions are exact to double precision.
constexpr double kSmallAngle = 1e-6;
}  // namespace

Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-12) {
    // First order: q = (1, v/2), renormalised.
    return Eigen::Quaterniond(1.0, 0.5 * rotation_vector.x(), 0.5 * rotation_vector.y(),
                              0.5 * rotation_vector.z())
        .normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

Eigen::Vector3d quaternionLog(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // same rotation, angle in [0, pi]
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v / q.w();  // atan2(s, w) / s -> 1 / w
  return 2.0 * std::atan2(s, q.w()) / s * v;
}

Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  const Eigen::Matrix3d W = skew(phi);
  if (a < kSmallAngle) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 6.0;
  const double a2 = a * a;
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(a)) / a2 * W +
         (a - std::sin(a)) / (a2 * a) * W * W;
}

Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  const Eigen::Matrix3d W = skew(phi);
  if (a < kSmallAngle) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 12.0;
  const double a2 = a * a;
  return Eigen::Matrix3d::Identity() + 0.5 * W +
         (1.0 / a2 - (1.0 + std::cos(a)) / (2.0 * a * std::sin(a))) * W * W;
}

}  // namespace adugs::vio

#pragma once
// SO(3) helpers shared by the IMU integrator, preintegration and the estimator factors.
// Convention: rotation vectors phi, Exp(phi) = quaternion of the rotation by |phi| about phi/|phi|;
// right Jacobian Jr(phi): Exp(phi + d) ~= Exp(phi) * Exp(Jr(phi) d).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace adugs::vio {

// [v]x such that skew(a) * b = a.cross(b).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// exp map of a rotation vector (exact for any angle).
Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector);

// log map: the rotation vector of q (angle in [0, pi]); q need not be normalised.
Eigen::Vector3d quaternionLog(const Eigen::Quaterniond& q);

// Right Jacobian of SO(3) and its inverse.
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& phi);
Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& phi);

}  // namespace adugs::vio

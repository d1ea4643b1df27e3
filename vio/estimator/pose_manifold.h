#pragma once
// The pose parameter block of the estimator: x = [p(3), q(4)] with q stored x, y, z, w (Eigen's
// coefficient order), T_W_B = (q, p). Tangent delta = [dp(3), dtheta(3)]:
//   Plus(x, delta) = [p + dp, q * Exp(dtheta)]      (right perturbation of the rotation)
//   Minus(y, x)    = [p_y - p_x, Log(q_x^-1 q_y)]
// Factors compute their Jacobians in this tangent space (tangent_cost_function.h) and hand Ceres
// ambient Jacobians J_ambient = J_tangent * quaternionLiftJacobian(q), lift * PlusJacobian = I,
// so that Ceres' product J_ambient * PlusJacobian gives back exactly J_tangent (and the factors
// stay correct with any manifold whose Plus has the same tangent, unlike the [I; 0] shortcut).
#include <ceres/manifold.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace adugs::vio {

constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;

class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseSize; }
  int TangentSize() const override { return kPoseTangentSize; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;  // 7x6 row-major
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;  // 6x7 row-major
};

// d dtheta / d q (3x4, columns x y z w) at q: the rotation rows of MinusJacobian, for unit q.
Eigen::Matrix<double, 3, 4> quaternionLiftJacobian(const Eigen::Quaterniond& q);

// d (q * Exp(dtheta)) / d dtheta (4x3, rows x y z w) at dtheta = 0.
Eigen::Matrix<double, 4, 3> quaternionPlusJacobian(const Eigen::Quaterniond& q);

// Views of a pose block.
inline Eigen::Map<const Eigen::Vector3d> posePosition(const double* x) {
  return Eigen::Map<const Eigen::Vector3d>(x);
}
inline Eigen::Map<const Eigen::Quaterniond> poseRotation(const double* x) {
  return Eigen::Map<const Eigen::Quaterniond>(x + 3);
}

// Packs a pose block from (p, q); q is normalised.
void setPose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double* x);

}  // namespace adugs::vio

// PoseManifold: Plus/Minus are inverse, and the Jacobians match finite differences.
#include "vio/estimator/pose_manifold.h"

#include <gtest/gtest.h>

#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

Vector7d samplePose() {
  Vector7d x;
  setPose(Eigen::Vector3d(1.0, -2.0, 0.5), quaternionExp(Eigen::Vector3d(0.4, -0.3, 1.2)), x.data());
  return x;
}

TEST(PoseManifold, MinusInvertsPlusAndRotatesOnTheRight) {
  const PoseManifold m;
  const Vector7d x = samplePose();
  Vector6d delta;
  delta << 0.1, -0.2, 0.3, 0.05, -0.4, 0.2;
  Vector7d y;
  Vector6d back;
  m.Plus(x.data(), delta.data(), y.data());
  m.Minus(y.data(), x.data(), back.data());
  EXPECT_LT((back - delta).norm(), 1e-12);
  // Right perturbation: q_y = q_x Exp(dtheta).
  const Eigen::Quaterniond expected = poseRotation(x.data()) * quaternionExp(delta.tail<3>());
  EXPECT_LT(expected.angularDistance(Eigen::Quaterniond(poseRotation(y.data()))), 1e-12);
}

TEST(PoseManifold, JacobiansMatchFiniteDifferencesAndLiftInvertsPlus) {
  const PoseManifold m;
  const Vector7d x = samplePose();
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus_jac;
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> minus_jac;
  m.PlusJacobian(x.data(), plus_jac.data());
  m.MinusJacobian(x.data(), minus_jac.data());
  const double h = 1e-6;
  Eigen::Matrix<double, 7, 6> plus_num;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    Vector7d a, b;
    d(k) = h;
    m.Plus(x.data(), d.data(), a.data());
    d(k) = -h;
    m.Plus(x.data(), d.data(), b.data());
    plus_num.col(k) = (a - b) / (2 * h);
  }
  EXPECT_LT((plus_jac - plus_num).norm(), 1e-9);
  EXPECT_LT((minus_jac * plus_jac - Eigen::Matrix<double, 6, 6>::Identity()).norm(), 1e-12);
  // MinusJacobian rows are d Minus(y, x) / dy at y = x along the unit sphere: check along Plus.
  EXPECT_LT((minus_jac * plus_num - Eigen::Matrix<double, 6, 6>::Identity()).norm(), 1e-8);
}

}  // namespace
}  // namespace adugs::vio

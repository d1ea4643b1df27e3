// The pose prior (vio/estimator/pose_prior_factor.h): hand-worked residual, analytic vs numeric Jacobian.
#include <gtest/gtest.h>

#include <array>

#include "tests/vio/jacobian_check.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/estimator/pose_prior_factor.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

std::array<double, 7> poseBlock(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()};
}

// 2 cm along x at sigma 1 cm, and 0.02 rad about z at sigma 0.01 rad: r = [2, 0, 0, 0, 0, 2].
TEST(PosePriorFactor, ResidualIsTheWhitenedDeviation) {
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d p0(0.1, -0.2, 0.05);
  const PosePriorFactor f(p0, q0, 0.01, 0.01);
  auto x = poseBlock(p0 + Eigen::Vector3d(0.02, 0, 0),
                     q0 * Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ())));
  const double* params[] = {x.data()};
  Eigen::Matrix<double, 6, 1> r;
  ASSERT_TRUE(f.Evaluate(params, r.data(), nullptr));
  Eigen::Matrix<double, 6, 1> expected;
  expected << 2, 0, 0, 0, 0, 2;
  EXPECT_LT((r - expected).norm(), 1e-12) << r.transpose();
}

TEST(PosePriorFactor, AnalyticJacobianMatchesNumericAwayFromThePrior) {
  const PoseManifold pm;
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(-0.7, Eigen::Vector3d(0.3, -1, 0.2).normalized()));
  const PosePriorFactor f({0.3, 0.1, -0.4}, q0, 0.05, 0.03);
  auto x = poseBlock({0.5, -0.2, 0.1}, q0 * quaternionExp(Eigen::Vector3d(0.3, -0.5, 0.8)));
  const auto check = testing::checkJacobians(f, {x.data()}, {&pm});
  EXPECT_TRUE(check.ok) << check.report;
}

}  // namespace
}  // namespace adugs::vio

// NEES of the window's relative poses against ground truth (vio/eval/consistency.h) on
// hand-worked cases: the error in the oldest frame's axes, the rotation on the right, the heading
// about gravity, unmatched estimates left out.
#include <gtest/gtest.h>

#include <cmath>

#include "vio/eval/consistency.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace consistency_test {

constexpr int64_t kSec = 1'000'000'000LL;

data::StampedPose at(int64_t t_ns, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  data::StampedPose s;
  s.t_ns = t_ns;
  s.p_W_B = p;
  s.q_W_B = q;
  return s;
}

RelativePoseEstimate estimate(int64_t from, int64_t to, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                              const Eigen::Matrix<double, 6, 1>& variances) {
  RelativePoseEstimate e;
  e.t_from_ns = from;
  e.t_to_ns = to;
  e.p_from_to = p;
  e.q_from_to = q;
  e.covariance = variances.asDiagonal();
  return e;
}

TEST(Consistency, NeesOfHandWorkedRelativePoses) {
  const Eigen::Quaterniond I = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond quarter_turn(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  // Truth: at 0 s at the origin, at 1 s one metre along x; at 2 s turned a quarter about z at
  // (1, 1, 0), at 3 s one metre along its own x, i.e. (1, 2, 0) in the world.
  const data::Trajectory gt = {at(0, {0, 0, 0}, I), at(1 * kSec, {1, 0, 0}, I),
                               at(2 * kSec, {1, 1, 0}, quarter_turn), at(3 * kSec, {1, 2, 0}, quarter_turn)};
  Eigen::Matrix<double, 6, 1> v;
  v << 0.01, 0.01, 0.01, 0.01, 0.01, 0.01;
  std::vector<RelativePoseEstimate> estimates;
  // 10 cm too far along x, sigma 10 cm: NEES 1 (position 1, heading 0).
  estimates.push_back(estimate(0, 1 * kSec, {1.1, 0, 0}, I, v));
  // Turned 0.1 rad too far about z, sigma 0.1 rad: NEES 1 (position 0, heading 1).
  estimates.push_back(estimate(0, 1 * kSec, {1, 0, 0}, quaternionExp(Eigen::Vector3d(0, 0, 0.1)), v));
  // In the turned frame: 10 cm off along its y (the world's -x), where sigma is 20 cm: 0.25. A
  // world-frame error (along the world's x, sigma 10 cm) would give 1.
  Eigen::Matrix<double, 6, 1> wide_y = v;
  wide_y(1) = 0.04;
  estimates.push_back(estimate(2 * kSec, 3 * kSec, {1, 0.1, 0}, I, wide_y));
  // No ground truth at 5 s: left out.
  estimates.push_back(estimate(0, 5 * kSec, {1, 0, 0}, I, v));
  const ConsistencyResult r = evaluateConsistency(estimates, gt);
  ASSERT_EQ(r.count, 3u);
  EXPECT_NEAR(r.nees_pose, (1.0 + 1.0 + 0.25) / 3, 1e-6);
  EXPECT_NEAR(r.nees_position, (1.0 + 0.0 + 0.25) / 3, 1e-6);
  EXPECT_NEAR(r.nees_yaw, (0.0 + 1.0 + 0.0) / 3, 1e-6);
  EXPECT_DOUBLE_EQ(r.within_95, 1.0);
}

TEST(Consistency, OverconfidentCovarianceFallsOutsideTheBound) {
  const Eigen::Quaterniond I = Eigen::Quaterniond::Identity();
  const data::Trajectory gt = {at(0, {0, 0, 0}, I), at(1 * kSec, {1, 0, 0}, I)};
  Eigen::Matrix<double, 6, 1> v = Eigen::Matrix<double, 6, 1>::Constant(1e-4);  // sigma 1 cm
  // 10 cm off with a 1 cm sigma: NEES 100, beyond the 95 % bound of 12.59.
  const ConsistencyResult r = evaluateConsistency({estimate(0, 1 * kSec, {1.1, 0, 0}, I, v)}, gt);
  ASSERT_EQ(r.count, 1u);
  EXPECT_NEAR(r.nees_pose, 100.0, 1e-6);
  EXPECT_DOUBLE_EQ(r.within_95, 0.0);
  // A covariance that is not positive definite is left out, not divided by.
  RelativePoseEstimate bad = estimate(0, 1 * kSec, {1.1, 0, 0}, I, v);
  bad.covariance(0, 0) = -1;
  EXPECT_EQ(evaluateConsistency({bad}, gt).count, 0u);
}

}  // namespace consistency_test
}  // namespace adugs::vio

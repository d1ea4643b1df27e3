// ATE statistics, RPE over distance and the whole evaluation, on hand-worked trajectories.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vio/eval/trajectory_eval.h"
#include "vio/eval/trajectory_metrics.h"
#include "tests/test_support.h"

namespace adugs::vio {
namespace {

using data::StampedPose;
using data::Trajectory;

using ::adugs::test::kDeg;

// Straight line along x: `n` poses `step_m` apart, 10 Hz, identity orientation.
Trajectory straightLine(int n, double step_m) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    StampedPose p;
    p.t_ns = 1'000'000'000LL + i * 100'000'000LL;
    p.p_W_B = Eigen::Vector3d(step_m * i, 0.0, 1.0);
    t.push_back(p);
  }
  return t;
}

Trajectory helix(int n) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double a = 0.02 * i;
    StampedPose p;
    p.t_ns = i * 50'000'000LL;
    p.p_W_B = Eigen::Vector3d(5 * std::cos(a), 5 * std::sin(a), 0.05 * i);
    p.q_W_B = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ());
    t.push_back(p);
  }
  return t;
}

TEST(ErrorStats, HandWorked) {
  const ErrorStats s = computeStats({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));  // (16 + 1 + 9 + 4) / 4
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std, as numpy / evo
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(computeStats({5.0, 1.0, 3.0}).median, 3.0);
  EXPECT_EQ(computeStats({}).count, 0u);
}

TEST(Ate, KnownOffsetsWithoutAlignment) {
  // Every pose displaced by 0.1 m or 0.3 m in alternating directions: RMSE sqrt((0.01 + 0.09) / 2).
  const Trajectory gt = helix(200);
  Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(std::sin(i), std::cos(3.0 * i), 0.5).normalized();
    est[i].p_W_B += (i % 2 ? 0.3 : 0.1) * dir;
  }
  const AteResult ate = computeAte(est, gt);
  EXPECT_NEAR(ate.translation.rmse, std::sqrt(0.05), 1e-12);
  EXPECT_NEAR(ate.translation.mean, 0.2, 1e-12);
  EXPECT_NEAR(ate.translation.std, 0.1, 1e-12);
  EXPECT_NEAR(ate.translation.median, 0.2, 1e-12);
  EXPECT_NEAR(ate.translation.min, 0.1, 1e-12);
  EXPECT_NEAR(ate.translation.max, 0.3, 1e-12);
  EXPECT_EQ(ate.translation.count, 200u);
  EXPECT_LT(ate.rotation.max, 1e-12);
}

TEST(Ate, KnownNoiseAfterSe3AlignmentInAnotherFrame) {
  // Noise made orthogonal to (1, x, y, z) of the ground truth has zero mean and zero
  // cross-covariance with the path, so the best se3 fit is exactly the frame change and the ATE
  // RMSE is exactly the noise's RMS.
  const Trajectory gt = helix(300);
  const int n = static_cast<int>(gt.size());
  Eigen::MatrixXd basis(n, 4);
  for (int i = 0; i < n; ++i) basis.row(i) << 1.0, gt[i].p_W_B.transpose();
  std::mt19937 rng(42);
  std::normal_distribution<double> normal(0.0, 0.05);
  Eigen::MatrixXd noise(n, 3);
  for (int i = 0; i < n; ++i) noise.row(i) << normal(rng), normal(rng), normal(rng);
  const Eigen::MatrixXd Q = basis.householderQr().householderQ() * Eigen::MatrixXd::Identity(n, 4);
  noise -= Q * (Q.transpose() * noise);
  const double expected_rmse = std::sqrt(noise.rowwise().squaredNorm().mean());

  SimilarityTransform T_E_G;
  T_E_G.R_G_E = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  T_E_G.t_G_E = Eigen::Vector3d(10, -20, 5);
  Trajectory noisy = gt;
  for (int i = 0; i < n; ++i) noisy[i].p_W_B += noise.row(i).transpose();
  const Trajectory est = T_E_G.apply(noisy);

  EvalOptions options;
  options.align = AlignMode::kSe3;
  const EvalResult r = evaluateTrajectory(est, gt, options);
  EXPECT_NEAR(r.ate.translation.rmse, expected_rmse, 1e-12);
  EXPECT_GT(expected_rmse, 0.07);  // about 0.05 * sqrt(3)
  EXPECT_LT(expected_rmse, 0.1);
  EXPECT_LT((r.T_G_E.R_G_E - T_E_G.R_G_E.transpose()).norm(), 1e-12);
}

TEST(Ate, KnownRotationError) {
  const Trajectory gt = helix(100);
  Trajectory est = gt;
  for (StampedPose& p : est)
    p.q_W_B = p.q_W_B * Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d(1, 2, 2) / 3.0);
  const AteResult ate = computeAte(est, gt);
  EXPECT_NEAR(ate.rotation.rmse, 2.0, 1e-9);
  EXPECT_NEAR(ate.rotation.min, 2.0, 1e-9);
  EXPECT_LT(ate.translation.max, 1e-15);
}

TEST(Rpe, ConstantScaleDriftGivesKnownPercentage) {
  // 100 m at 0.1 m spacing; the estimate travels 2 % too far: every segment is 2 % off.
  const Trajectory gt = straightLine(1001, 0.1);
  Trajectory est = gt;
  for (StampedPose& p : est) p.p_W_B.x() *= 1.02;
  EXPECT_NEAR(pathLength(gt), 100.0, 1e-9);
  const auto rpe = computeRpe(est, gt, {10.0, 50.0, 200.0});
  ASSERT_EQ(rpe.size(), 3u);
  EXPECT_EQ(rpe[0].translation_m.count, 901u);  // starts at 0..90 m
  EXPECT_NEAR(rpe[0].translation_pct.mean, 2.0, 1e-9);
  EXPECT_NEAR(rpe[0].translation_pct.max, 2.0, 1e-9);
  EXPECT_NEAR(rpe[0].translation_m.rmse, 0.2, 1e-9);
  EXPECT_NEAR(rpe[1].translation_pct.median, 2.0, 1e-9);
  EXPECT_EQ(rpe[1].translation_m.count, 501u);
  EXPECT_LT(rpe[1].rotation_deg.max, 1e-12);
  EXPECT_EQ(rpe[2].translation_m.count, 0u);  // longer than the path

  // sim3 alignment removes a pure scale error.
  EvalOptions options;
  options.align = AlignMode::kSim3;
  options.rpe_lengths_m = {10.0};
  Trajectory bent = gt;  // sim3 needs a non-collinear path: add a sideways wiggle
  for (size_t i = 0; i < bent.size(); ++i) bent[i].p_W_B.y() = std::sin(0.01 * i);
  Trajectory scaled = bent;
  for (StampedPose& p : scaled) p.p_W_B *= 1.02;
  EXPECT_LT(evaluateTrajectory(scaled, bent, options).rpe[0].translation_pct.max, 1e-9);
}

TEST(Rpe, ConstantYawDriftGivesKnownRotationError) {
  // Heading error growing by 0.5 deg per metre travelled: every 10 m segment is 5 deg off in yaw.
  const Trajectory gt = straightLine(501, 0.1);
  Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i)
    est[i].q_W_B = Eigen::AngleAxisd(0.5 * kDeg * 0.1 * i, Eigen::Vector3d::UnitZ());
  const auto rpe = computeRpe(est, gt, {10.0});
  EXPECT_NEAR(rpe[0].rotation_deg.mean, 5.0, 1e-9);
  EXPECT_NEAR(rpe[0].rotation_deg.max, 5.0, 1e-9);
  EXPECT_NEAR(rpe[0].yaw_deg.mean, 5.0, 1e-9);
  // A roll drift is a rotation error but no yaw error.
  for (size_t i = 0; i < est.size(); ++i)
    est[i].q_W_B = Eigen::AngleAxisd(0.5 * kDeg * 0.1 * i, Eigen::Vector3d::UnitX());
  const auto roll = computeRpe(est, gt, {10.0});
  EXPECT_NEAR(roll[0].rotation_deg.mean, 5.0, 1e-9);
  EXPECT_LT(roll[0].yaw_deg.max, 1e-9);
}

TEST(Rpe, SegmentLengthTolerance) {
  // Poses 1 m apart: a 2.5 m segment is 0.5 m (20 %) off any pair, beyond the 10 % tolerance.
  const Trajectory gt = straightLine(20, 1.0);
  EXPECT_EQ(computeRpe(gt, gt, {2.5})[0].translation_m.count, 0u);
  // With 25 %: 3 m segments (the tie between 2 m and 3 m goes to the later pose) from 0..16 m.
  EXPECT_EQ(computeRpe(gt, gt, {2.5}, 0.25)[0].translation_m.count, 17u);
  EXPECT_THROW(computeRpe(gt, gt, {0.0}), std::invalid_argument);
}

TEST(Rpe, DefaultLengths) {
  EXPECT_EQ(defaultRpeLengths(100.0), (std::vector<double>{10, 20, 30, 40, 50}));
  const auto l = defaultRpeLengths(58.349);
  ASSERT_EQ(l.size(), 5u);
  EXPECT_NEAR(l[0], 5.8, 1e-12);
  EXPECT_NEAR(l[4], 29.0, 1e-12);
  EXPECT_TRUE(defaultRpeLengths(0.0).empty());
}

TEST(Evaluate, NoAssociationExplainsWhy) {
  const Trajectory gt = helix(50);
  Trajectory est = gt;
  for (StampedPose& p : est) p.t_ns += 1'000'000'000'000LL;  // 1000 s later
  try {
    evaluateTrajectory(est, gt);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no associated poses"), std::string::npos) << e.what();
  }
}

TEST(Evaluate, CountsAndLength) {
  const Trajectory gt = straightLine(101, 0.1);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); i += 2) est.push_back(gt[i]);  // half the rate
  EvalOptions options;
  options.align = AlignMode::kNone;
  const EvalResult r = evaluateTrajectory(est, gt, options);
  EXPECT_EQ(r.est_poses, 51u);
  EXPECT_EQ(r.gt_poses, 101u);
  EXPECT_EQ(r.pairs.size(), 51u);
  EXPECT_NEAR(r.gt_length_m, 10.0, 1e-12);
  EXPECT_EQ(r.align_pairs_used, 0u);
  ASSERT_EQ(r.rpe.size(), 5u);  // 1, 2, 3, 4, 5 m
  EXPECT_DOUBLE_EQ(r.rpe[0].length_m, 1.0);
  EXPECT_EQ(r.ate.translation.max, 0.0);
}

// The initialisation's transient left out: an estimate 1 m off along one axis in its first 3 s
// (a helix, poses every 0.05 s from t = 0) and exact after. With se3 alignment over everything the
// offset spreads into every pose; skipping the first 3 s leaves the exact poses, aligned on their
// own.
TEST(Evaluate, SkipFirstLeavesTheTransientOut) {
  const Trajectory gt = helix(201);  // 10 s
  Trajectory est = gt;
  for (StampedPose& p : est)
    if (p.t_ns < 3'000'000'000LL) p.p_W_B.y() += 1.0;  // poses 0..59
  EvalOptions options;
  const EvalResult all = evaluateTrajectory(est, gt, options);
  EXPECT_GT(all.ate.translation.rmse, 0.2);
  options.skip_first_s = 3.0;
  const EvalResult settled = evaluateTrajectory(est, gt, options);
  EXPECT_EQ(settled.est_poses, 201u);  // the input, as before
  ASSERT_EQ(settled.pairs.size(), 141u);  // from t = 3 s on: poses 60..200
  EXPECT_EQ(settled.est_matched.front().t_ns, gt[60].t_ns);
  EXPECT_LT(settled.ate.translation.rmse, 1e-9);
  EXPECT_NEAR(settled.gt_length_m, pathLength(Trajectory(gt.begin() + 60, gt.end())), 1e-9);
  EXPECT_EQ(settled.gt_poses, 201u);
  // The correct rate's span starts where the evaluation does: every pose left is correct.
  EXPECT_NEAR(settled.correct_rate.span_s, 7.0, 1e-9);
  EXPECT_DOUBLE_EQ(settled.correct_rate.correct_rate, 1.0);

  options.skip_first_s = 10.5;  // past the last pose (t = 10 s)
  try {
    evaluateTrajectory(est, gt, options);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nothing left to evaluate"), std::string::npos) << e.what();
  }
  options.skip_first_s = -1;
  EXPECT_THROW(evaluateTrajectory(est, gt, options), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio

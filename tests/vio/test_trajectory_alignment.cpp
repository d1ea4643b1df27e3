// Association by time and alignment (se3, sim3, posyaw, none) with hand-made transforms.
#include <gtest/gtest.h>

#include <cmath>

#include "vio/eval/trajectory_alignment.h"
#include "vio/eval/trajectory_metrics.h"

namespace adugs::vio {
namespace {

using data::StampedPose;
using data::Trajectory;

constexpr int64_t kMs = 1000000;

// A 3-D wiggly loop sampled at 20 Hz, body yawing along the path and pitching a little.
Trajectory wigglyLoop(int n = 400, int64_t t0_ns = 1000 * kMs) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double s = 0.05 * i;
    StampedPose p;
    p.t_ns = t0_ns + i * 50 * kMs;
    p.p_W_B = Eigen::Vector3d(3.0 * std::cos(0.4 * s), 2.0 * std::sin(0.4 * s),
                              1.0 + 0.3 * std::sin(1.3 * s));
    p.q_W_B = Eigen::AngleAxisd(0.4 * s, Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(0.1 * std::sin(s), Eigen::Vector3d::UnitY());
    t.push_back(p);
  }
  return t;
}

// Applies p -> scale * R * p + t (and R to orientations): the gt -> est frame change.
Trajectory transformed(const Trajectory& in, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                       double scale = 1.0) {
  SimilarityTransform T;
  T.R_G_E = R;
  T.t_G_E = t;
  T.scale = scale;
  return T.apply(in);
}

Eigen::Matrix3d someRotation() {
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

double ateRmse(const Trajectory& est, const Trajectory& gt, AlignMode mode, int frames = -1) {
  return computeAte(alignTrajectory(est, gt, mode, frames).apply(est), gt).translation.rmse;
}

// ---- association -----------------------------------------------------------------------------

Trajectory stamps(const std::vector<int64_t>& t_ms) {
  Trajectory t;
  for (int64_t ms : t_ms) {
    StampedPose p;
    p.t_ns = ms * kMs;
    t.push_back(p);
  }
  return t;
}

TEST(Associate, OffsetWithinAndBeyondMaxDt) {
  const Trajectory gt = stamps({0, 50, 100, 150, 200});
  const Trajectory est = stamps({3, 53, 103, 153, 203});
  EXPECT_EQ(associate(est, gt, 10 * kMs).size(), 5u);
  EXPECT_EQ(associate(est, gt, 3 * kMs).size(), 5u);  // |dt| == max is kept (as evo)
  EXPECT_TRUE(associate(est, gt, 2 * kMs).empty());
  const auto pairs = associate(est, gt, 10 * kMs);
  for (size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(pairs[i].est_index, i);
    EXPECT_EQ(pairs[i].gt_index, i);
  }
}

TEST(Associate, GapsInGroundTruthAndEstimate) {
  const Trajectory gt = stamps({0, 50, 100, /* gap */ 400, 450});
  const Trajectory est = stamps({1, 51, 99, 200, 250, 300, 399, /* gap */ 600});
  const auto pairs = associate(est, gt, 10 * kMs);
  ASSERT_EQ(pairs.size(), 4u);
  EXPECT_EQ(pairs[2].est_index, 2u);
  EXPECT_EQ(pairs[2].gt_index, 2u);
  EXPECT_EQ(pairs[3].est_index, 6u);  // 399 -> 400
  EXPECT_EQ(pairs[3].gt_index, 3u);
}

TEST(Associate, OneToOneKeepsTheClosest) {
  // Estimate at 200 Hz against ground truth at 20 Hz, 2 ms late: each gt pose is matched once,
  // by the estimate closest to it.
  std::vector<int64_t> est_ms, gt_ms;
  for (int i = 0; i < 200; ++i) est_ms.push_back(2 + 5 * i);
  for (int i = 0; i < 20; ++i) gt_ms.push_back(50 * i);
  const auto pairs = associate(stamps(est_ms), stamps(gt_ms), 10 * kMs);
  ASSERT_EQ(pairs.size(), 20u);
  for (size_t k = 0; k < pairs.size(); ++k) {
    EXPECT_EQ(pairs[k].gt_index, k);
    EXPECT_EQ(pairs[k].est_index, 10 * k);  // 2 ms off, the neighbours are 3 and 7 ms off
  }
  // A tie (est exactly between two gt poses) goes to the earlier gt pose.
  const auto tie = associate(stamps({25}), stamps({0, 50}), 30 * kMs);
  ASSERT_EQ(tie.size(), 1u);
  EXPECT_EQ(tie[0].gt_index, 0u);
}

TEST(Associate, RejectsUnsortedInput) {
  EXPECT_THROW(associate(stamps({0, 100, 50}), stamps({0, 50}), kMs), std::invalid_argument);
}

// ---- alignment ------------------------------------------------------------------------------

TEST(Align, ParseModes) {
  EXPECT_EQ(parseAlignMode("se3"), AlignMode::kSe3);
  EXPECT_EQ(parseAlignMode("sim3"), AlignMode::kSim3);
  EXPECT_EQ(parseAlignMode("posyaw"), AlignMode::kPosYaw);
  EXPECT_EQ(parseAlignMode("none"), AlignMode::kNone);
  EXPECT_STREQ(alignModeName(AlignMode::kPosYaw), "posyaw");
  EXPECT_THROW(parseAlignMode("SE3"), std::invalid_argument);
}

TEST(Align, Se3RecoversAKnownRigidTransform) {
  const Trajectory gt = wigglyLoop();
  const Eigen::Matrix3d R_E_G = someRotation();
  const Eigen::Vector3d t_E_G(4.0, -7.5, 2.25);
  const Trajectory est = transformed(gt, R_E_G, t_E_G);
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kSe3);
  EXPECT_LT((T.R_G_E - R_E_G.transpose()).norm(), 1e-12);
  EXPECT_LT((T.t_G_E + R_E_G.transpose() * t_E_G).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(T.scale, 1.0);
  const AteResult ate = computeAte(T.apply(est), gt);
  EXPECT_LT(ate.translation.max, 1e-12);
  EXPECT_LT(ate.rotation.max, 1e-9);  // degrees
  EXPECT_GT(ateRmse(est, gt, AlignMode::kNone), 1.0);
}

TEST(Align, Sim3RecoversScale) {
  const Trajectory gt = wigglyLoop();
  const Trajectory est = transformed(gt, someRotation(), Eigen::Vector3d(1, 2, 3), 0.37);
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kSim3);
  EXPECT_NEAR(T.scale, 1.0 / 0.37, 1e-12);
  EXPECT_LT(ateRmse(est, gt, AlignMode::kSim3), 1e-12);
  EXPECT_GT(ateRmse(est, gt, AlignMode::kSe3), 0.5);  // se3 cannot undo a scale error
}

// Hand-worked: an estimate 2 % longer than the ground truth is shrunk by 1 / 1.02, and its
// length error is +2 %; one 0.37 of the length is 63 % short.
TEST(Align, LengthErrorIsTheEstimatesExtraLengthInPercent) {
  const Trajectory gt = wigglyLoop();
  const Trajectory longer = transformed(gt, someRotation(), Eigen::Vector3d(1, 2, 3), 1.02);
  EXPECT_NEAR(alignTrajectory(longer, gt, AlignMode::kSim3).lengthErrorPercent(), 2.0, 1e-9);
  const Trajectory shorter = transformed(gt, someRotation(), Eigen::Vector3d(1, 2, 3), 0.37);
  EXPECT_NEAR(alignTrajectory(shorter, gt, AlignMode::kSim3).lengthErrorPercent(), -63.0, 1e-9);
  EXPECT_DOUBLE_EQ(alignTrajectory(longer, gt, AlignMode::kSe3).lengthErrorPercent(), 0.0);
}

TEST(Align, NeverReturnsAReflection) {
  // A planar (z = 0) path: the covariance has rank 2 and a mirror fits as well as the rotation.
  Trajectory gt = wigglyLoop();
  for (StampedPose& p : gt) p.p_W_B.z() = 0.0;
  const Trajectory est = transformed(gt, someRotation(), Eigen::Vector3d(0.5, 0, 0));
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kSe3);
  EXPECT_NEAR(T.R_G_E.determinant(), 1.0, 1e-12);
  EXPECT_LT(ateRmse(est, gt, AlignMode::kSe3), 1e-12);
}

TEST(Align, PosYawRecoversYawAndTranslation) {
  const Trajectory gt = wigglyLoop();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Trajectory est = transformed(gt, R, Eigen::Vector3d(-3, 8, 0.4));
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kPosYaw);
  EXPECT_LT((T.R_G_E - R.transpose()).norm(), 1e-12);
  EXPECT_LT(ateRmse(est, gt, AlignMode::kPosYaw), 1e-12);
}

TEST(Align, PosYawCannotRemoveARollError) {
  const Trajectory gt = wigglyLoop();
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Trajectory est = transformed(gt, roll, Eigen::Vector3d(1, 1, 1));
  EXPECT_LT(ateRmse(est, gt, AlignMode::kSe3), 1e-12);
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kPosYaw);
  EXPECT_NEAR(T.R_G_E(2, 2), 1.0, 1e-15);                 // only a rotation about z
  EXPECT_GT(ateRmse(est, gt, AlignMode::kPosYaw), 0.05);  // 0.1 rad of roll over a 4 m wide loop
}

TEST(Align, FirstFramesOnly) {
  // Exact for the first 100 poses, then drifting away: aligning on the first 100 keeps them exact.
  const Trajectory gt = wigglyLoop();
  Trajectory est = transformed(gt, someRotation(), Eigen::Vector3d(1, 2, 3));
  for (size_t i = 100; i < est.size(); ++i)
    est[i].p_W_B += Eigen::Vector3d(0.01, 0.0, 0.0) * (i - 100.0);
  const Trajectory aligned = alignTrajectory(est, gt, AlignMode::kSe3, 100).apply(est);
  const AteResult ate = computeAte(aligned, gt);
  for (size_t i = 0; i < 100; ++i) EXPECT_LT(ate.translation_m[i], 1e-12) << i;
  EXPECT_NEAR(ate.translation_m.back(), 0.01 * 299, 1e-9);
  EXPECT_GT(computeAte(alignTrajectory(est, gt, AlignMode::kSe3).apply(est), gt).translation_m[0],
            0.1);
}

TEST(Align, SingleFrameUsesTheFirstPose) {
  const Trajectory gt = wigglyLoop();
  Trajectory est = transformed(gt, someRotation(), Eigen::Vector3d(1, 2, 3));
  for (size_t i = 1; i < est.size(); ++i)
    est[i].p_W_B += Eigen::Vector3d(0, 0, 0.001 * i);  // drift
  const SimilarityTransform T = alignTrajectory(est, gt, AlignMode::kSe3, 1);
  EXPECT_LT((T.R_G_E - someRotation().transpose()).norm(), 1e-12);  // from the first orientation
  const Trajectory aligned = T.apply(est);
  EXPECT_LT((aligned[0].p_W_B - gt[0].p_W_B).norm(), 1e-12);
  // posyaw on one pose: the yaw of the first orientation only.
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(-1.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const SimilarityTransform Y =
      alignTrajectory(transformed(gt, yaw, Eigen::Vector3d::Zero()), gt, AlignMode::kPosYaw, 1);
  EXPECT_LT((Y.R_G_E - yaw.transpose()).norm(), 1e-12);
}

TEST(Align, DegenerateInputsThrow) {
  Trajectory line = wigglyLoop(50);
  for (size_t i = 0; i < line.size(); ++i) line[i].p_W_B = Eigen::Vector3d(0.1 * i, 0.2 * i, 0.0);
  EXPECT_THROW(alignTrajectory(line, line, AlignMode::kSe3), std::invalid_argument);
  EXPECT_THROW(alignTrajectory(line, line, AlignMode::kSim3), std::invalid_argument);
  EXPECT_NO_THROW(alignTrajectory(line, line, AlignMode::kPosYaw));
  EXPECT_NO_THROW(alignTrajectory(line, line, AlignMode::kNone));
  const Trajectory gt = wigglyLoop();
  EXPECT_THROW(alignTrajectory(gt, gt, AlignMode::kSim3, 2), std::invalid_argument);
  EXPECT_THROW(alignTrajectory(gt, Trajectory(gt.begin(), gt.end() - 1), AlignMode::kSe3),
               std::invalid_argument);
  EXPECT_THROW(alignTrajectory({}, {}, AlignMode::kSe3), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio

// OpenLORIS' correct rate on hand-worked cases, alone and inside the whole evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "vio/eval/correct_rate.h"
#include "vio/eval/trajectory_eval.h"

namespace adugs::vio {
namespace {

using data::StampedPose;
using data::Trajectory;

constexpr int64_t kSec = 1'000'000'000LL;
constexpr int64_t kMs = 1'000'000LL;

// Matched estimated poses (ground truth from 0.5 s to 10.0 s, thresholds 1 m and 30 deg):
//   t [s]  pos [m]  angle [deg]  correct?            gap to the next matched pose (max 1 s)
//   1.0    0.2      5            yes                 1.5 - 1.0 = 0.5
//   1.5    1.5      1            no (position)       -
//   2.0    0.5      40           no (angle)          -
//   4.0    1.0      30           yes (<= both)       4.2 - 4.0 = 0.2
//   4.2    0.1      1            yes                 9.5 - 4.2 = 5.3 -> 1.0 (lost in between)
//   9.5    0.3      2            yes                 last: t_end - 9.5 = 0.5
// t_end = max(last estimate 9.5, last ground truth 10.0) = 10.0
// correct time = 0.5 + 0.2 + 1.0 + 0.5 = 2.2 s; span = 10.0 - 0.5 (first ground truth) = 9.5 s
// CR = 2.2 / 9.5 = 0.231578947...
const std::vector<int64_t> kTimes = {1000 * kMs, 1500 * kMs, 2000 * kMs,
                                     4000 * kMs, 4200 * kMs, 9500 * kMs};
const std::vector<double> kPosition = {0.2, 1.5, 0.5, 1.0, 0.1, 0.3};
const std::vector<double> kAngle = {5.0, 1.0, 40.0, 30.0, 1.0, 2.0};

TEST(CorrectRate, HandWorked) {
  const CorrectRateResult r = computeCorrectRate(kTimes, kPosition, kAngle, 500 * kMs, 10 * kSec);
  EXPECT_EQ(r.poses, 6u);
  EXPECT_EQ(r.correct_poses, 4u);
  EXPECT_NEAR(r.correct_time_s, 2.2, 1e-12);
  EXPECT_NEAR(r.span_s, 9.5, 1e-12);
  EXPECT_NEAR(r.correct_rate, 2.2 / 9.5, 1e-12);
}

TEST(CorrectRate, ThresholdsAndGapAreOptions) {
  // A 2 m / 45 deg threshold makes 1.5 s (gap 0.5) and 2.0 s (gap 2.0 -> 1.0) correct too:
  // 2.2 + 0.5 + 1.0 = 3.7 s. With a 0.25 s max gap instead: 0.25 + 0.2 + 0.25 + 0.25 = 0.95 s.
  CorrectRateOptions loose;
  loose.max_position_m = 2.0;
  loose.max_angle_deg = 45.0;
  CorrectRateResult r = computeCorrectRate(kTimes, kPosition, kAngle, 500 * kMs, 10 * kSec, loose);
  EXPECT_EQ(r.correct_poses, 6u);
  EXPECT_NEAR(r.correct_time_s, 3.7, 1e-12);
  CorrectRateOptions short_gap;
  short_gap.max_gap_ns = 250 * kMs;
  r = computeCorrectRate(kTimes, kPosition, kAngle, 500 * kMs, 10 * kSec, short_gap);
  EXPECT_NEAR(r.correct_time_s, 0.95, 1e-12);
}

TEST(CorrectRate, EstimateEndingAfterTheGroundTruthSetsTheSpan) {
  // Ground truth 0..10 s, the last estimate at 12 s: t_end = 12, the last pose has no gap.
  // Correct: 8.0 (gap 4 -> 1) and 12.0 (gap 0): CR = 1 / 12.
  const CorrectRateResult r =
      computeCorrectRate({8 * kSec, 12 * kSec}, {0.0, 0.0}, {0.0, 0.0}, 0, 10 * kSec);
  EXPECT_NEAR(r.correct_time_s, 1.0, 1e-12);
  EXPECT_NEAR(r.span_s, 12.0, 1e-12);
  EXPECT_NEAR(r.correct_rate, 1.0 / 12.0, 1e-12);
}

TEST(CorrectRate, EdgeCasesAndBadInput) {
  const CorrectRateResult none = computeCorrectRate({}, {}, {}, 0, 10 * kSec);
  EXPECT_EQ(none.poses, 0u);
  EXPECT_EQ(none.correct_rate, 0.0);
  EXPECT_TRUE(std::isnan(computeCorrectRate({kSec}, {0.0}, {0.0}, kSec, kSec).correct_rate));
  // A NaN error is never correct.
  EXPECT_EQ(computeCorrectRate({0}, {std::nan("")}, {0.0}, 0, kSec).correct_poses, 0u);
  EXPECT_THROW(computeCorrectRate({0, kSec}, {0.0}, {0.0, 0.0}, 0, kSec), std::invalid_argument);
  EXPECT_THROW(computeCorrectRate({kSec, kSec}, {0.0, 0.0}, {0.0, 0.0}, 0, kSec),
               std::invalid_argument);
  EXPECT_THROW(computeCorrectRate({0}, {0.0}, {0.0}, kSec, 0), std::invalid_argument);
  CorrectRateOptions bad;
  bad.max_gap_ns = 0;
  EXPECT_THROW(computeCorrectRate({0}, {0.0}, {0.0}, 0, kSec, bad), std::invalid_argument);
  bad = CorrectRateOptions{};
  bad.max_angle_deg = -1.0;
  EXPECT_THROW(computeCorrectRate({0}, {0.0}, {0.0}, 0, kSec, bad), std::invalid_argument);
}

// Poses at 10 Hz from first_ns to last_ns along a wave (x = t, y = sin t).
Trajectory line(int64_t first_ns, int64_t last_ns) {
  Trajectory t;
  for (int64_t t_ns = first_ns; t_ns <= last_ns; t_ns += 100 * kMs) {
    StampedPose p;
    p.t_ns = t_ns;
    p.p_W_B = Eigen::Vector3d(data::nsToSec(t_ns), std::sin(data::nsToSec(t_ns)), 1.0);
    t.push_back(p);
  }
  return t;
}

TEST(CorrectRate, InTheEvaluation) {
  // 101 poses 1.0 .. 11.0 s; poses 30..49 (4.0 .. 5.9 s) are 2 m off: wrong. Without alignment
  // the correct poses 0..29 and 50..99 count 0.1 s each (8.0 s), pose 100 ends at t_end (0 s).
  // CR = 8 / (11 - 1) = 0.8.
  const Trajectory gt = line(kSec, 11 * kSec);
  Trajectory est = gt;
  for (size_t i = 30; i < 50; ++i) est[i].p_W_B.z() += 2.0;
  EvalOptions options;
  options.align = AlignMode::kNone;
  EvalResult r = evaluateTrajectory(est, gt, options);
  EXPECT_EQ(r.correct_rate.poses, 101u);
  EXPECT_EQ(r.correct_rate.correct_poses, 81u);
  EXPECT_NEAR(r.correct_rate.correct_time_s, 8.0, 1e-9);
  EXPECT_NEAR(r.correct_rate.correct_rate, 0.8, 1e-9);
  // A 2.5 m threshold accepts them all: 100 gaps of 0.1 s.
  options.correct_rate.max_position_m = 2.5;
  r = evaluateTrajectory(est, gt, options);
  EXPECT_NEAR(r.correct_rate.correct_rate, 1.0, 1e-9);
}

TEST(CorrectRate, OnlyWhereTheGroundTruthCovers) {
  // TUM-VI-like: the mocap sees the start (1..3 s) and the end (9..11 s) only; the estimate runs
  // 0..12 s and is 100 m off wherever there is no ground truth. Those poses are not matched (no
  // ground-truth pose within max_dt), so they change neither the ATE nor the CR:
  // matched 1.0..3.0 (21) and 9.0..11.0 (21); ATE 0; correct time 20 * 0.1 + min(9 - 3, 1)
  // + 20 * 0.1 + 0 (11.0 = t_end) = 5 s over 11 - 1 = 10 s: CR 0.5.
  Trajectory gt = line(kSec, 3 * kSec);
  const Trajectory end = line(9 * kSec, 11 * kSec);
  gt.insert(gt.end(), end.begin(), end.end());
  Trajectory est = line(0, 12 * kSec);
  for (StampedPose& p : est) {
    const bool covered =
        (p.t_ns >= kSec && p.t_ns <= 3 * kSec) || (p.t_ns >= 9 * kSec && p.t_ns <= 11 * kSec);
    if (!covered) p.p_W_B.y() += 100.0;
  }
  EvalOptions options;
  options.align = AlignMode::kNone;
  const EvalResult r = evaluateTrajectory(est, gt, options);
  EXPECT_EQ(r.est_poses, 121u);
  EXPECT_EQ(r.pairs.size(), 42u);
  EXPECT_EQ(r.ate.translation.max, 0.0);
  EXPECT_NEAR(r.correct_rate.correct_time_s, 5.0, 1e-9);
  EXPECT_NEAR(r.correct_rate.correct_rate, 0.5, 1e-9);
  // se3 alignment on the covered part only finds the identity as well.
  options.align = AlignMode::kSe3;
  EXPECT_NEAR(evaluateTrajectory(est, gt, options).ate.translation.max, 0.0, 1e-9);
}

}  // namespace
}  // namespace adugs::vio

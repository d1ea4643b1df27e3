// HOTA against hand-worked cases (the formulas in tracking/eval/hota.h). The same cases give the same
// values through TrackEval's own hota.py (checked outside CI, doc/results.md), and
// CmdEvalMot.HotaReproducesTrackEvalOnTud checks real tracker output against TrackEval's figures.
#include <gtest/gtest.h>

#include <cmath>

#include "tracking/eval/hota.h"

namespace adugs::tracking {
namespace {

// A 10 x 10 box at x; a box of the same left, top and width with height h lies inside it.
LabelledBox square(int64_t id, double x) { return {id, Box::fromCorners(x, 0, x + 10, 10)}; }
LabelledBox lower(int64_t id, double x, double h) { return {id, Box::fromCorners(x, 0, x + 10, h)}; }

TEST(Hota, PerfectTrackingScoresOne) {
  HotaAccumulator acc;
  for (int f = 0; f < 3; ++f) acc.addFrame({square(1, 0), square(2, 50)}, {square(7, 0), square(8, 50)});
  const HotaSummary s = acc.summary();
  EXPECT_DOUBLE_EQ(s.hota(), 1.0);
  EXPECT_DOUBLE_EQ(s.detA(), 1.0);
  EXPECT_DOUBLE_EQ(s.assA(), 1.0);
  EXPECT_DOUBLE_EQ(s.locA(), 1.0);
  EXPECT_DOUBLE_EQ(s.tp[18], 6);
}

// One person over 4 frames, tracked as id A in frames 1-2 and as id B in frames 3-4, boxes exact:
// every box a TP at every alpha (DetA 1); each pair (1, A), (1, B) has c = 2, n_g = 4, n_h = 2:
// A = 2 / (4 + 2 - 2) = 0.5 for all 4 TPs -> AssA 0.5, HOTA sqrt(0.5); AssRe c / n_g = 0.5,
// AssPr c / n_h = 1.
TEST(Hota, AnIdentitySplitHalvesTheAssociationAccuracy) {
  HotaAccumulator acc;
  acc.addFrame({square(1, 0)}, {square(100, 0)});
  acc.addFrame({square(1, 0)}, {square(100, 0)});
  acc.addFrame({square(1, 0)}, {square(200, 0)});
  acc.addFrame({square(1, 0)}, {square(200, 0)});
  const HotaSummary s = acc.summary();
  EXPECT_DOUBLE_EQ(s.detA(), 1.0);
  EXPECT_NEAR(s.assA(), 0.5, 1e-12);
  EXPECT_NEAR(s.hota(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(s.assRe(), 0.5, 1e-12);
  EXPECT_NEAR(s.assPr(), 1.0, 1e-12);
}

// One frame, the hypothesis covers 62 % of the gt box (IoU 0.62): a TP for the 12 alphas
// 0.05..0.60, a FN + FP for the 7 alphas 0.65..0.95. DetA = AssA = HOTA = 12 / 19. LocA: 0.62 where
// matched and, as TrackEval, 1 for alphas without any TP: (12 x 0.62 + 7) / 19.
TEST(Hota, LocalisationThresholdsAreAveraged) {
  HotaAccumulator acc;
  acc.addFrame({square(1, 0)}, {lower(5, 0, 6.2)});
  const HotaSummary s = acc.summary();
  EXPECT_NEAR(s.detA(), 12.0 / 19, 1e-12);
  EXPECT_NEAR(s.assA(), 12.0 / 19, 1e-12);
  EXPECT_NEAR(s.hota(), 12.0 / 19, 1e-12);
  EXPECT_NEAR(s.locA(), (12 * 0.62 + 7) / 19, 1e-12);
  EXPECT_DOUBLE_EQ(s.tp[11], 1);  // alpha 0.60
  EXPECT_DOUBLE_EQ(s.fn[12], 1);  // alpha 0.65
  EXPECT_DOUBLE_EQ(s.fp[12], 1);
}

// The global alignment decides the matching, not the frame's IoU. Gt 1 and hypothesis A agree
// exactly in frames 1-3; in frame 4 A has IoU 0.6 and a one-frame hypothesis B IoU 0.9.
//   frame 4: row sum 1.5, so S / (row + col - S) = 0.6 / 1.5 = 0.4 for A, 0.9 / 1.5 = 0.6 for B;
//   P(1, A) = 3.4, A(1, A) = 3.4 / (4 + 4 - 3.4) = 0.739; P(1, B) = 0.6, A(1, B) = 0.6 / 4.4 = 0.136;
//   scores 0.739 x 0.6 = 0.443 > 0.136 x 0.9 = 0.123: A is matched, B is a FP.
//   alphas 0.05..0.60 (12): TP 4, FP 1 -> DetA 0.8, c(1, A) = 4 -> AssA 4 / (4 + 4 - 4) = 1;
//   alphas 0.65..0.95 (7): TP 3, FN 1, FP 2 -> DetA 0.5, AssA 3 / (4 + 4 - 3) = 0.6.
TEST(Hota, GlobalAlignmentDecidesTheMatching) {
  HotaAccumulator acc;
  for (int f = 0; f < 3; ++f) acc.addFrame({square(1, 0)}, {square(10, 0)});
  acc.addFrame({square(1, 0)}, {lower(10, 0, 6), lower(20, 0, 9)});
  const HotaSummary s = acc.summary();
  EXPECT_DOUBLE_EQ(s.tp[11], 4);
  EXPECT_DOUBLE_EQ(s.fp[11], 1);
  EXPECT_DOUBLE_EQ(s.tp[12], 3);
  EXPECT_DOUBLE_EQ(s.fp[12], 2);
  EXPECT_NEAR(s.detA(), (12 * 0.8 + 7 * 0.5) / 19, 1e-12);
  EXPECT_NEAR(s.assA(), (12 * 1.0 + 7 * 0.6) / 19, 1e-12);
  EXPECT_NEAR(s.hota(), (12 * std::sqrt(0.8) + 7 * std::sqrt(0.5 * 0.6)) / 19, 1e-12);
}

TEST(Hota, EmptyOutputMissesEverything) {
  HotaAccumulator acc;
  acc.addFrame({square(1, 0)}, {});
  acc.addFrame({square(1, 0)}, {});
  const HotaSummary s = acc.summary();
  EXPECT_DOUBLE_EQ(s.hota(), 0.0);
  EXPECT_DOUBLE_EQ(s.fn[0], 2);
  EXPECT_DOUBLE_EQ(s.locA(), 1.0);
}

// Combining sequences: TP, FN, FP summed, AssA weighted by TP (TrackEval's COMBINED_SEQ).
TEST(Hota, CombinedSequencesWeighAssociationByTruePositives) {
  HotaAccumulator perfect, split;
  for (int f = 0; f < 4; ++f) perfect.addFrame({square(1, 0)}, {square(9, 0)});
  for (int f = 0; f < 4; ++f) split.addFrame({square(1, 0)}, {square(f < 2 ? 100 : 200, 0)});
  const HotaSummary all = combineHotaSummaries({perfect.summary(), split.summary()});
  EXPECT_DOUBLE_EQ(all.tp[0], 8);
  EXPECT_NEAR(all.assA(), (4 * 1.0 + 4 * 0.5) / 8, 1e-12);
  EXPECT_NEAR(all.hota(), std::sqrt(0.75), 1e-12);
}

}  // namespace
}  // namespace adugs::tracking

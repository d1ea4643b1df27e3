#include <gtest/gtest.h>

#include "tracking/eval/mot_metrics.h"

namespace adugs::tracking {
namespace {

LabelledBox lb(int64_t id, double cx) { return {id, Box{cx, 50, 20, 40}}; }

// Hand-worked sequence of 4 frames, 2 GT objects (ids 1, 2):
//   f1: hyp 10 on gt 1, hyp 20 on gt 2                 -> 2 matches
//   f2: hyp 10 on gt 1, gt 2 missed, hyp 30 far away   -> 1 match, 1 FN, 1 FP
//   f3: hyp 10 on gt 1, hyp 30 now on gt 2             -> 2 matches, 1 IDSW (gt 2: 20 -> 30)
//   f4: hyp 10 slightly off gt 1 (IoU 0.6) and hyp 40 exactly on gt 1: the previous
//       correspondence 1-10 is kept (IoU >= 0.5), 40 is a FP; gt 2 matched by 30.
// GT = 8, matches = 7, FN = 1, FP = 2, IDSW = 1 -> MOTA = 1 - 4/8 = 0.5.
TEST(MotMetrics, HandWorkedSequence) {
  MotAccumulator acc(0.5);
  acc.addFrame({lb(1, 100), lb(2, 300)}, {lb(10, 100), lb(20, 300)});
  acc.addFrame({lb(1, 100), lb(2, 300)}, {lb(10, 100), lb(30, 600)});
  acc.addFrame({lb(1, 100), lb(2, 300)}, {lb(10, 100), lb(30, 300)});
  // Width 20 shifted by 5: intersection 15x40, union 25x40 -> IoU 0.6.
  acc.addFrame({lb(1, 100), lb(2, 300)}, {lb(10, 105), lb(40, 100), lb(30, 300)});
  const MotCounts& c = acc.counts();
  EXPECT_EQ(c.frames, 4);
  EXPECT_EQ(c.ground_truth, 8);
  EXPECT_EQ(c.matches, 7);
  EXPECT_EQ(c.false_negatives, 1);
  EXPECT_EQ(c.false_positives, 2);
  EXPECT_EQ(c.id_switches, 1);
  ASSERT_EQ(acc.idSwitches().size(), 1u);  // the event: frame 3, gt 2 from hypothesis 20 to 30
  EXPECT_EQ(acc.idSwitches()[0].frame, 3);
  EXPECT_EQ(acc.idSwitches()[0].gt_id, 2);
  EXPECT_EQ(acc.idSwitches()[0].previous_hypothesis, 20);
  EXPECT_EQ(acc.idSwitches()[0].hypothesis, 30);
  EXPECT_DOUBLE_EQ(c.mota(), 0.5);
  EXPECT_NEAR(c.motp(), (6 * 1.0 + 0.6) / 7, 1e-12);
  EXPECT_DOUBLE_EQ(c.recall(), 7.0 / 8.0);

  // Summary. gt 1 matched 4/4 (mostly tracked), gt 2 3/4 (partially); gt 2 goes matched -> missed
  // once between its first and last match (1 fragmentation). Predictions: 2 + 2 + 2 + 3 = 9.
  // Frames with IoU >= 0.5 per pair: (1,10) 4, (1,40) 1, (2,20) 1, (2,30) 2 (f3, f4). The best
  // one-to-one assignment is 1-10 and 2-30: IDTP = 6, IDF1 = 2*6 / (8 + 9), IDP = 6/9, IDR = 6/8.
  const MotSummary s = acc.summary();
  EXPECT_EQ(s.unique_objects, 2);
  EXPECT_EQ(s.mostly_tracked, 1);
  EXPECT_EQ(s.partially_tracked, 1);
  EXPECT_EQ(s.mostly_lost, 0);
  EXPECT_EQ(s.fragmentations, 1);
  EXPECT_EQ(s.predictions, 9);
  EXPECT_EQ(s.idtp, 6);
  EXPECT_DOUBLE_EQ(s.idf1(), 12.0 / 17.0);
  EXPECT_DOUBLE_EQ(s.idp(), 6.0 / 9.0);
  EXPECT_DOUBLE_EQ(s.idr(), 6.0 / 8.0);
  EXPECT_DOUBLE_EQ(s.precision(), 7.0 / 9.0);
  const MotSummary twice = combineMotSummaries({s, s});
  EXPECT_DOUBLE_EQ(twice.idf1(), s.idf1());
  EXPECT_EQ(twice.fragmentations, 2);
}

TEST(MotMetrics, HypothesesOnIgnoredRegionsAreNotFalsePositives) {
  MotAccumulator acc(0.5);
  acc.addFrame({lb(1, 100)}, {lb(10, 100), lb(11, 300), lb(12, 500)}, {Box{300, 50, 20, 40}});
  EXPECT_EQ(acc.counts().matches, 1);
  EXPECT_EQ(acc.counts().ignored_hypotheses, 1);
  EXPECT_EQ(acc.counts().false_positives, 1);
}

TEST(MotMetrics, IntersectionOverUnionHandWorked) {
  // 10x10 boxes overlapping on a 5x10 strip: 50 / (100 + 100 - 50) = 1/3.
  EXPECT_NEAR(intersectionOverUnion(Box{5, 5, 10, 10}, Box{10, 5, 10, 10}), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(intersectionOverUnion(Box{5, 5, 10, 10}, Box{30, 5, 10, 10}), 0.0);
  EXPECT_EQ(intersectionOverUnion(Box{5, 5, 0, 10}, Box{5, 5, 10, 10}), 0.0);
}

}  // namespace
}  // namespace adugs::tracking

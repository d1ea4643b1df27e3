// dropGroupBoxes (tracking/detect/detector.h): a weak box around people found one by one goes,
// everything that could be a real object stays. Hand-made frames; the real detector's group box
// on vtest.avi is YoloxDetector.NoBoxAroundTwoPeopleItFoundAlone (test_yolox_detector.cpp).
#include <gtest/gtest.h>

#include "tracking/detect/detector.h"

namespace adugs::tracking {
namespace {

Detection person(double left, double top, double w, double h, double score) {
  return {Box::fromCorners(left, top, left + w, top + h), 0, score};
}

// Two people standing side by side (about 100 x 300 px each).
std::vector<Detection> twoPeople() { return {person(100, 100, 100, 300, 0.85), person(220, 110, 100, 290, 0.8)}; }

TEST(GroupBoxes, AWeakBoxAroundTwoPeopleFoundAloneIsDropped) {
  std::vector<Detection> frame = twoPeople();
  frame.push_back(person(500, 120, 80, 250, 0.9));
  frame.push_back(person(80, 80, 260, 340, 0.35));  // holds both side-by-side people whole
  std::vector<Detection> kept = dropGroupBoxes(frame);
  ASSERT_EQ(kept.size(), 3u);
  for (const Detection& d : kept) EXPECT_GT(d.score, 0.5) << d.box.w;
  // Of any class: YOLOX-nano called the one it was measured on a train (COCO 6).
  frame.back().class_id = 6;
  kept = dropGroupBoxes(frame);
  ASSERT_EQ(kept.size(), 3u);
  for (const Detection& d : kept) EXPECT_EQ(d.class_id, 0);
}

TEST(GroupBoxes, BoxesThatMayBeObjectsStay) {
  // Holding only one person: a person in front of a bigger one.
  std::vector<Detection> one = {person(100, 100, 100, 300, 0.85), person(80, 80, 260, 340, 0.35)};
  EXPECT_EQ(dropGroupBoxes(one).size(), 2u);
  // Scoring above one of the people inside: a confident object with weak parts in it.
  std::vector<Detection> confident = twoPeople();
  confident.push_back(person(80, 80, 260, 340, 0.82));
  EXPECT_EQ(dropGroupBoxes(confident).size(), 3u);
  // Less than kGroupInsideMin of the second person inside (70 of its 100 px width).
  std::vector<Detection> cut = twoPeople();
  cut.push_back(person(80, 80, 210, 340, 0.35));
  EXPECT_EQ(dropGroupBoxes(cut).size(), 3u);
  // 90 of its 100 px inside: a member.
  cut.back() = person(80, 80, 230, 340, 0.35);
  EXPECT_EQ(dropGroupBoxes(cut).size(), 2u);
}

TEST(GroupBoxes, NonMaximumSuppressionDropsThemToo) {
  std::vector<Detection> frame = twoPeople();
  frame.push_back(person(80, 80, 260, 340, 0.35));
  frame.push_back(person(102, 101, 99, 300, 0.6));  // a duplicate of the first person: NMS's case
  const std::vector<Detection> kept = suppressOverlaps(frame, 0.3, 0.45);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_DOUBLE_EQ(kept[0].score, 0.85);
  EXPECT_DOUBLE_EQ(kept[1].score, 0.8);
}

}  // namespace
}  // namespace adugs::tracking

// tracking/object_motion: which tracked objects the motion cue's points say are static, moving or
// unknown; and the masker leaving the static ones unmasked.
#include <gtest/gtest.h>

#include <memory>

#include <opencv2/core.hpp>

#include "tracking/dynamic_masker.h"
#include "tracking/object_motion.h"
#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {
namespace {

TrackedObject object(int64_t id, double cx, double cy, double w, double h) {
  TrackedObject o;
  o.id = id;
  o.box = {cx, cy, w, h};
  o.detected = true;
  return o;
}

// n points spread inside the box centred at (cx, cy), the first `moving` of them moving.
std::vector<MotionCuePoint> pointsIn(double cx, double cy, int n, int moving) {
  std::vector<MotionCuePoint> points;
  for (int i = 0; i < n; ++i) {
    MotionCuePoint p;
    p.pixel = cv::Point2f(static_cast<float>(cx - 8 + 4 * (i % 5)), static_cast<float>(cy - 8 + 4 * (i / 5)));
    p.moving = i < moving;
    points.push_back(p);
  }
  return points;
}

TEST(ObjectMotion, StaticAfterEnoughFramesWithPointsAndNoMotion) {
  ObjectMotionClassifier c({/*static_frames=*/10, /*min_points=*/4});
  const std::vector<TrackedObject> parked = {object(1, 100, 100, 40, 30)};
  for (int k = 1; k <= 10; ++k) {
    EXPECT_EQ(c.state(1), ObjectMotion::kUnknown) << k;
    c.update(parked, pointsIn(100, 100, 6, 0), true);
  }
  EXPECT_EQ(c.state(1), ObjectMotion::kStatic);
  EXPECT_EQ(c.staticIds(), std::set<int64_t>{1});
  EXPECT_EQ(c.everStatic(), 1u);
  // One noisy moving point among many does not make it move.
  c.update(parked, pointsIn(100, 100, 12, 1), true);
  EXPECT_EQ(c.state(1), ObjectMotion::kStatic);
  // Forgotten when no longer tracked.
  c.update({}, {}, true);
  EXPECT_EQ(c.state(1), ObjectMotion::kUnknown);
  EXPECT_TRUE(c.staticIds().empty());
  EXPECT_EQ(c.everStatic(), 1u);
}

TEST(ObjectMotion, OnceMovingAlwaysMovingAndTooFewPointsStayUnknown) {
  ObjectMotionClassifier c({/*static_frames=*/3, /*min_points=*/4});
  const std::vector<TrackedObject> objects = {object(1, 100, 100, 40, 30), object(2, 300, 100, 40, 30)};
  std::vector<MotionCuePoint> points = pointsIn(100, 100, 6, 3);  // object 1 walks
  const std::vector<MotionCuePoint> few = pointsIn(300, 100, 3, 0);  // object 2: too little texture
  points.insert(points.end(), few.begin(), few.end());
  c.update(objects, points, true);
  EXPECT_EQ(c.state(1), ObjectMotion::kMoving);
  for (int k = 0; k < 20; ++k) c.update(objects, pointsIn(100, 100, 6, 0), true);  // then stands still
  EXPECT_EQ(c.state(1), ObjectMotion::kMoving);  // a person who stops walks on: still masked
  EXPECT_EQ(c.state(2), ObjectMotion::kUnknown);
  // Points outside every box count for none.
  ObjectMotionClassifier d({3, 4});
  for (int k = 0; k < 5; ++k) d.update({object(3, 100, 100, 10, 10)}, pointsIn(400, 400, 10, 10), true);
  EXPECT_EQ(d.state(3), ObjectMotion::kUnknown);
  // A translating camera cannot confirm that anything stands still.
  ObjectMotionClassifier moving_camera({3, 4});
  for (int k = 0; k < 20; ++k) moving_camera.update({object(5, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 0), false);
  EXPECT_EQ(moving_camera.state(5), ObjectMotion::kUnknown);
  moving_camera.update({object(5, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 3), false);  // but motion shows
  EXPECT_EQ(moving_camera.state(5), ObjectMotion::kMoving);
  // static_frames 0: never static.
  ObjectMotionClassifier never({0, 4});
  for (int k = 0; k < 50; ++k) never.update({object(4, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 0), true);
  EXPECT_EQ(never.state(4), ObjectMotion::kUnknown);
}

// The masker segments every tracked box except those set static.
TEST(ObjectMotion, MaskerLeavesStaticObjectsUnmasked) {
  DynamicMaskerOptions o;
  o.segment_async = false;
  o.sort.min_hits = 1;
  o.refinement.erode_radius_px = 0;
  o.refinement.dilate_radius_px = 1;
  DynamicMasker masker(o, std::make_unique<FilledBoxSegmenter>());
  const cv::Mat image(240, 320, CV_8UC1, cv::Scalar(128));
  std::vector<Detection> dets(2);
  dets[0].box = Box{60, 60, 40, 40};
  dets[1].box = Box{220, 160, 40, 40};
  dets[1].class_id = 2;
  DynamicMaskResult r = masker.process(image, dets);
  ASSERT_EQ(r.objects.size(), 2u);
  EXPECT_EQ(r.mask.at<uint8_t>(60, 60), 255);
  EXPECT_EQ(r.mask.at<uint8_t>(160, 220), 255);
  const int64_t car = r.objects[0].box.cx > 150 ? r.objects[0].id : r.objects[1].id;
  masker.setStaticObjects({car});
  r = masker.process(image, dets);
  EXPECT_EQ(r.mask.at<uint8_t>(60, 60), 255);
  EXPECT_EQ(r.mask.at<uint8_t>(160, 220), 0);
  EXPECT_EQ(r.objects.size(), 2u);  // still tracked, only not masked
}

}  // namespace
}  // namespace adugs::tracking

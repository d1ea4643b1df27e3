// tracking/object_motion: which tracked objects the motion cue's points say are static, moving or
// unknown; and the masker leaving the static ones unmasked.
#include <gtest/gtest.h>

#include <memory>

#include <opencv2/core.hpp>

#include "tests/tracking/rendered_panel_flight.h"
#include "tracking/detect/motion_cue.h"
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
    c.update(parked, pointsIn(100, 100, 6, 0), false);
  }
  EXPECT_EQ(c.state(1), ObjectMotion::kStatic);
  EXPECT_EQ(c.staticIds(), std::set<int64_t>{1});
  EXPECT_EQ(c.everStatic(), 1u);
  // One noisy moving point among many does not make it move.
  c.update(parked, pointsIn(100, 100, 12, 1), false);
  EXPECT_EQ(c.state(1), ObjectMotion::kStatic);
  // Forgotten when no longer tracked.
  c.update({}, {}, false);
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
  c.update(objects, points, false);
  EXPECT_EQ(c.state(1), ObjectMotion::kMoving);
  for (int k = 0; k < 20; ++k) c.update(objects, pointsIn(100, 100, 6, 0), false);  // then stands still
  EXPECT_EQ(c.state(1), ObjectMotion::kMoving);  // a person who stops walks on: still masked
  EXPECT_EQ(c.state(2), ObjectMotion::kUnknown);
  // Points outside every box count for none.
  ObjectMotionClassifier d({3, 4});
  for (int k = 0; k < 5; ++k) d.update({object(3, 100, 100, 10, 10)}, pointsIn(400, 400, 10, 10), false);
  EXPECT_EQ(d.state(3), ObjectMotion::kUnknown);
  // Without a camera model (the object's size cannot give its range) a translating camera cannot
  // confirm that anything stands still.
  ObjectMotionClassifier moving_camera({3, 4});
  for (int k = 0; k < 20; ++k) moving_camera.update({object(5, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 0), true);
  EXPECT_EQ(moving_camera.state(5), ObjectMotion::kUnknown);
  moving_camera.update({object(5, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 3), true);  // but motion shows
  EXPECT_EQ(moving_camera.state(5), ObjectMotion::kMoving);
  // static_frames 0: never static.
  ObjectMotionClassifier never({0, 4});
  for (int k = 0; k < 50; ++k) never.update({object(4, 100, 100, 40, 30)}, pointsIn(100, 100, 6, 0), false);
  EXPECT_EQ(never.state(4), ObjectMotion::kUnknown);
}

// A translating camera: the 1 m panel of the rendered flight as an object of a class 1 m tall.
// Standing, its points slide as static points at the range its size gives (3 m): static. Going
// the camera's way at half its speed, they slide half as far, as static points twice as far away
// would, so the motion cue cannot tell (no moving point): it must not be judged static. Nor when
// the class's height is wrong (2 m: the size says 6 m) or unknown.
TEST(ObjectMotion, ATranslatingCameraConfirmsStaticWhenTheObjectsSizeAgrees) {
  const Scene scene;
  const auto judge = [&](const Eigen::Vector2d& panel_step, double class_height) {
    MotionCue cue(kCamera);
    ObjectMotionOptions options;
    options.static_frames = 5;
    options.class_height_m = {{7, class_height}};
    if (class_height <= 0) options.class_height_m.clear();
    ObjectMotionClassifier c(options, kCamera);
    int moving_points = 0;
    for (int k = 0; k < 12; ++k) {
      const PanelFlightFrame f = panelFlightFrame(scene, {0.04, 0, 0}, 0.3, panel_step, k);
      cue.detect(f.image, f.R_Ccur_Cprev, f.v_C, 1 / kFlightFps);
      const cv::Rect r = cv::boundingRect(f.panel_mask);
      TrackedObject panel = object(1, r.x + r.width / 2.0 - 0.5, r.y + r.height / 2.0 - 0.5, r.width, r.height);
      panel.class_id = 7;
      EXPECT_EQ(cue.translating(), k > 0);
      c.update({panel}, cue.points(), cue.translating());
      for (const MotionCuePoint& p : cue.points()) moving_points += p.moving && f.panel_mask.at<uint8_t>(cv::Point(p.pixel));
    }
    return std::make_pair(c.state(1), moving_points);
  };
  EXPECT_EQ(judge({0, 0}, 1.0).first, ObjectMotion::kStatic);
  const auto [half_speed, moving_points] = judge({0.02, 0}, 1.0);
  EXPECT_EQ(moving_points, 0) << "the cue alone should not see this motion";
  EXPECT_EQ(half_speed, ObjectMotion::kUnknown);
  EXPECT_EQ(judge({0, 0}, 2.0).first, ObjectMotion::kUnknown);
  EXPECT_EQ(judge({0, 0}, 0).first, ObjectMotion::kUnknown);  // a class of no known height
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

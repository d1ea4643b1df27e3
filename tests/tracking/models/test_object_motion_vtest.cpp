// On real video (opencv-doc's vtest.avi = PETS09-S2L1, a static camera over a square): YOLOX-nano's
// boxes, the motion cue and the object-motion states together mask the people who walk, and leave
// the white van parked at the top right unmasked, its features kept (issue 30).
#include <gtest/gtest.h>

#include <map>
#include <memory>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "data/camera_model.h"
#include "tests/test_support.h"
#include "tracking/detect/detector_factory.h"
#include "tracking/detect/motion_cue.h"
#include "tracking/dynamic_masker.h"
#include "tracking/object_motion.h"
#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {
namespace {

constexpr int kPerson = 0, kCar = 2, kTruck = 7;  // COCO ids

TEST(ObjectMotionOnVideo, ThePeopleWalkingAreMaskedTheParkedVanIsNot) {
  const std::string& video = test::kPedestrianVideo;
  const auto model = test::sharedModelsDir() / "yolox_nano" / "yolox_nano.onnx";
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  ADUGS_REQUIRE_SHARED(model);
  cv::VideoCapture capture(video);
  ASSERT_TRUE(capture.isOpened());
  const std::unique_ptr<Detector> detector = makeDetector(model.string());
  const data::CameraModel camera(768, 576, 768, 768, 384, 288);  // adugs live's guess for a video
  MotionCue cue(camera);
  DynamicMaskerOptions options;
  options.segment_async = false;
  DynamicMasker masker(options, std::make_unique<FilledBoxSegmenter>());
  ObjectMotionClassifier states(options.object_motion);

  // 8 s at 10 Hz; the static camera: no rotation between frames.
  std::map<int64_t, int> class_of, frames_seen;
  DynamicMaskResult last;
  cv::Mat frame, grey;
  for (int k = 0; k < 80 && capture.read(frame); ++k) {
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
    std::vector<Detection> prompts = cue.detect(grey, Eigen::Matrix3d::Identity());
    const std::vector<Detection> boxes = detector->detect(frame);
    prompts.insert(prompts.end(), boxes.begin(), boxes.end());
    masker.setStaticObjects(states.staticIds());
    last = masker.process(frame, prompts);
    states.update(last.objects, cue.points(), cue.translating());
    for (const TrackedObject& o : last.objects) {
      class_of[o.id] = o.class_id;
      ++frames_seen[o.id];
    }
  }
  ASSERT_FALSE(last.mask.empty());
  // The van: a car or truck box whose centre lies in the top-right corner, there all along.
  int vans = 0, people = 0, people_masked = 0;
  for (const TrackedObject& o : last.objects) {
    const cv::Point centre(static_cast<int>(o.box.cx), static_cast<int>(o.box.cy));
    const bool masked = last.mask.at<uint8_t>(centre) == 255;
    if ((o.class_id == kCar || o.class_id == kTruck) && o.box.cx > 600 && o.box.cx < 740 && o.box.cy < 120 &&
        frames_seen[o.id] >= 40) {
      ++vans;
      EXPECT_EQ(states.state(o.id), ObjectMotion::kStatic) << "track " << o.id;
      EXPECT_FALSE(masked) << "the parked van (track " << o.id << ") is masked";
    }
    if (o.class_id == kPerson && states.state(o.id) == ObjectMotion::kMoving) {
      ++people;
      if (masked) ++people_masked;
    }
  }
  EXPECT_EQ(vans, 1);
  EXPECT_GE(people, 3);                 // people walking across the square at the end
  EXPECT_EQ(people_masked, people);     // every one judged moving is masked
  EXPECT_GE(states.everStatic(), 1u);
}

}  // namespace
}  // namespace adugs::tracking

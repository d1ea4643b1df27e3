#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "tracking/detect/yolox_detector.h"

namespace adugs::tracking {
namespace {

const std::string& kVideo = test::kPedestrianVideo;

// One anchor of the stride-16 grid (416 input: 52x52 stride-8 cells come first) at cell (3, 2):
// x, y offsets 0.5, 0.25 -> centre (3.5 * 16, 2.25 * 16) = (56, 36) in the input; log w, h =
// log 2, log 4 -> 32 x 64; with the image scaled by 0.5 into the input: (112, 72), 64 x 128.
TEST(YoloxDecode, HandWorkedAnchor) {
  const int rows = 52 * 52 + 26 * 26 + 13 * 13;
  cv::Mat out = cv::Mat::zeros(rows, 85, CV_32F);
  const int row = 52 * 52 + 2 * 26 + 3;
  float* a = out.ptr<float>(row);
  a[0] = 0.5f;
  a[1] = 0.25f;
  a[2] = std::log(2.0f);
  a[3] = std::log(4.0f);
  a[4] = 0.9f;      // objectness
  a[5 + 2] = 0.8f;  // car
  // A confident but non-dynamic class elsewhere (class 60, dining table) is filtered out.
  out.at<float>(10, 4) = 0.99f;
  out.at<float>(10, 5 + 60) = 0.99f;
  const auto d = decodeYoloxOutput(out, 416, 0.5, YoloxOptions{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].box.cx, 112, 1e-4);
  EXPECT_NEAR(d[0].box.cy, 72, 1e-4);
  EXPECT_NEAR(d[0].box.w, 64, 1e-4);
  EXPECT_NEAR(d[0].box.h, 128, 1e-4);
  EXPECT_EQ(d[0].class_id, 2);
  EXPECT_NEAR(d[0].score, 0.72, 1e-6);
}

TEST(YoloxDetector, FindsThePedestriansOfTheOpenCvVideo) {
  const auto model = test::sharedModelsDir() / "yolox_nano" / "yolox_nano.onnx";
  ADUGS_REQUIRE_SHARED(model);
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  YoloxDetector detector(model.string());
  cv::VideoCapture video(kVideo);
  ASSERT_TRUE(video.isOpened());
  cv::Mat frame;
  int persons = 0, frames = 0;
  for (int k = 0; k < 100 && video.read(frame); ++k) {
    if (k % 25 != 0) continue;  // frames 0, 25, 50, 75
    ++frames;
    for (const Detection& d : detector.detect(frame)) {
      if (d.class_id != 0) {  // a van and a car are parked at the top right, nothing else
        EXPECT_TRUE(d.class_id == 2 || d.class_id == 7) << d.class_id;
        EXPECT_GT(d.box.cx, 600);
        EXPECT_LT(d.box.cy, 120);
        continue;
      }
      EXPECT_GT(d.box.h, d.box.w) << "standing people are taller than wide";
      EXPECT_GT(d.box.cx, 0);
      EXPECT_LT(d.box.cx, frame.cols);
      EXPECT_GT(d.box.cy, 0);
      EXPECT_LT(d.box.cy, frame.rows);
      ++persons;
    }
  }
  ASSERT_EQ(frames, 4);
  std::cout << "YOLOX-nano on vtest.avi: " << persons << " people in 4 frames\n";
  EXPECT_GE(persons, 12);  // 4-8 people are visible in each of these frames
  EXPECT_LE(persons, 32);
  // Grey input gives detections too.
  cv::Mat grey;
  cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
  EXPECT_FALSE(detector.detect(grey).empty());
}

// Frame 768 of vtest.avi: two people one behind the other, found one by one, and (before
// dropGroupBoxes) a weaker box (0.42) around both that would have masked the floor between them.
TEST(YoloxDetector, NoBoxAroundTwoPeopleItFoundAlone) {
  const auto model = test::sharedModelsDir() / "yolox_nano" / "yolox_nano.onnx";
  ADUGS_REQUIRE_SHARED(model);
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  cv::VideoCapture video(kVideo);
  ASSERT_TRUE(video.set(cv::CAP_PROP_POS_FRAMES, 767));
  cv::Mat frame;
  ASSERT_TRUE(video.read(frame));
  const Box front = Box::fromCorners(272, 237, 310, 335), behind = Box::fromCorners(280, 178, 308, 254);
  bool found_front = false, found_behind = false;
  YoloxDetector detector(model.string());
  for (const Detection& d : detector.detect(frame)) {
    found_front = found_front || intersectionOverUnion(d.box, front) > 0.7;
    found_behind = found_behind || intersectionOverUnion(d.box, behind) > 0.7;
    const cv::Rect2d r = d.box.rect();
    const bool holds_both = (r & front.rect()).area() > 0.8 * front.rect().area() &&
                            (r & behind.rect()).area() > 0.8 * behind.rect().area();
    EXPECT_FALSE(holds_both) << "a box around both people: " << r << " score " << d.score;
  }
  EXPECT_TRUE(found_front);
  EXPECT_TRUE(found_behind);
}

TEST(YoloxDetector, BadModelFilesAreNamed) {
  EXPECT_THROW(YoloxDetector("/nonexistent/model.onnx"), data::InputError);
  test::TempDir tmp("adugs_yolox_bad");
  test::writeText(tmp / "text.onnx", "this is not a model\n");
  try {
    YoloxDetector((tmp / "text.onnx").string());
    FAIL() << "loaded a text file";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("text.onnx"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adugs::tracking

// Darknet detectors through OpenCV dnn: the [yolo] output decoding on a hand-worked row, the real
// Yolo-Fastest-1.1-XL model on the real pedestrians of OpenCV's vtest.avi, the model-file factory
// and bad model files.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <opencv2/videoio.hpp>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "tracking/detect/darknet_detector.h"
#include "tracking/detect/detector_factory.h"

namespace adugs::tracking {
namespace {

const std::string& kVideo = test::kPedestrianVideo;

// Row (cx, cy, w, h) = (0.5, 0.25, 0.1, 0.4) of a 800x600 image -> centre (400, 150), 80 x 240;
// class scores (already times objectness in OpenCV's region layer): person 0.7.
TEST(DarknetDecode, HandWorkedRow) {
  cv::Mat rows = cv::Mat::zeros(3, 85, CV_32F);
  float* a = rows.ptr<float>(1);
  a[0] = 0.5f, a[1] = 0.25f, a[2] = 0.1f, a[3] = 0.4f, a[4] = 0.9f;
  a[5 + 0] = 0.7f;
  rows.at<float>(2, 5 + 60) = 0.95f;  // a confident dining table: not a dynamic class
  rows.at<float>(0, 5 + 2) = 0.2f;    // a car below the threshold
  const auto d = decodeDarknetOutput(rows, cv::Size(800, 600), DarknetOptions{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].box.cx, 400, 1e-3);
  EXPECT_NEAR(d[0].box.cy, 150, 1e-3);
  EXPECT_NEAR(d[0].box.w, 80, 1e-3);
  EXPECT_NEAR(d[0].box.h, 240, 1e-3);
  EXPECT_EQ(d[0].class_id, 0);
  EXPECT_NEAR(d[0].score, 0.7, 1e-6);
}

TEST(DarknetDetector, YoloFastestFindsThePedestriansOfTheOpenCvVideo) {
  const auto dir = test::sharedModelsDir() / "yolo-fastest-1.1_coco";
  ADUGS_REQUIRE_SHARED(dir);
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  // Through the factory: the .cfg is found beside the .weights.
  const std::unique_ptr<Detector> detector = makeDetector((dir / "yolo-fastest-1.1-xl.weights").string());
  cv::VideoCapture video(kVideo);
  cv::Mat frame;
  int persons = 0, frames = 0;
  for (int k = 0; k < 100 && video.read(frame); ++k) {
    if (k % 25 != 0) continue;  // frames 0, 25, 50, 75: 4-8 people visible in each
    ++frames;
    for (const Detection& d : detector->detect(frame)) {
      EXPECT_TRUE(dynamicCocoClasses().count(d.class_id)) << d.class_id;
      if (d.class_id != 0) continue;  // the parked van and car; this small model also calls a
                                      // walker a bicycle or dog now and then
      EXPECT_GT(d.box.h, d.box.w) << "standing people are taller than wide";
      EXPECT_GT(d.box.cy, 100);
      ++persons;
    }
  }
  ASSERT_EQ(frames, 4);
  std::cout << "Yolo-Fastest-1.1-XL on vtest.avi: " << persons << " people in 4 frames\n";
  EXPECT_GE(persons, 12);
  EXPECT_LE(persons, 32);
}

TEST(DarknetDetector, BadModelFilesAreNamed) {
  test::TempDir tmp("adugs_darknet_bad");
  test::writeText(tmp / "m.weights", "not weights\n");
  // No .cfg beside the weights.
  try {
    makeDetector((tmp / "m.weights").string());
    FAIL();
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m.cfg"), std::string::npos) << e.what();
  }
  test::writeText(tmp / "m.cfg", "[net]\nbatch=1\n[convolutional]\nfilters=8\n");
  try {
    makeDetector((tmp / "m.weights").string());
    FAIL();
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("width and height"), std::string::npos) << e.what();
  }
  try {
    makeDetector((tmp / "model.tflite").string());
    FAIL();
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown detector model format '.tflite'"), std::string::npos) << e.what();
  }
  // An ultralytics training checkpoint: the user is told how to export it.
  try {
    makeDetector((tmp / "yolo11n.pt").string());
    FAIL();
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("yolo export model=yolo11n.pt format=torchscript"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace adugs::tracking

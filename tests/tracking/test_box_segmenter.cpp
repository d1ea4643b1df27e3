#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "tests/test_support.h"
#include "tests/tracking/simulated_street.h"
#include "tracking/segment/grabcut_segmenter.h"

namespace adugs::tracking {
namespace {

TEST(BoxSegmenter, ClippedRectAndFilledBoxes) {
  EXPECT_EQ(clippedRect(Box{10, 10, 10, 10}, 100, 100), cv::Rect(5, 5, 10, 10));
  EXPECT_EQ(clippedRect(Box{2, 98, 10, 10}, 100, 100), cv::Rect(0, 93, 7, 7));
  EXPECT_TRUE(clippedRect(Box{-50, 10, 10, 10}, 100, 100).empty());
  FilledBoxSegmenter s;
  const cv::Mat m =
      s.segment(cv::Mat::zeros(100, 100, CV_8UC1), {Box{10, 10, 10, 10}, Box{12, 12, 10, 10}});
  // Union of [5,15)x[5,15) and [7,17)x[7,17): 100 + 100 - 8*8 = 136 pixels.
  EXPECT_EQ(cv::countNonZero(m), 136);
}

// A textured disc on a differently textured background: GrabCut keeps the disc, not the box
// corners; the filled box would add the 21 % of the box outside the disc.
TEST(GrabCutSegmenter, SeparatesADiscFromItsBox) {
  cv::Mat image(240, 320, CV_8UC3);
  cv::RNG rng(5);
  rng.fill(image, cv::RNG::UNIFORM, cv::Scalar(20, 120, 20), cv::Scalar(60, 170, 60));  // greenish
  cv::Mat disc = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::circle(disc, {160, 120}, 50, cv::Scalar(255), cv::FILLED);
  cv::Mat red(image.size(), CV_8UC3);
  rng.fill(red, cv::RNG::UNIFORM, cv::Scalar(20, 20, 150), cv::Scalar(70, 70, 230));
  red.copyTo(image, disc);
  GrabCutSegmenter s;
  const cv::Mat m = s.segment(image, {Box{160, 120, 104, 104}});
  const double inter = cv::countNonZero(m & disc), uni = cv::countNonZero(m | disc);
  EXPECT_GT(inter / uni, 0.9);
  EXPECT_EQ(s.lastFallbacks(), 0);
  // Grey input works too (converted), and a tiny box is filled.
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat tiny = s.segment(grey, {Box{20, 20, 6, 6}});
  EXPECT_EQ(cv::countNonZero(tiny), 36);
  EXPECT_EQ(s.lastFallbacks(), 1);
  EXPECT_THROW(s.segment(cv::Mat(), {}), std::invalid_argument);
}

// A loose box (the motion cue's: the bounding box of moving points, widened) around a grey disc
// whose texture is close to the background's: from the box alone GrabCut keeps much of the box;
// the cue's points as prompts (moving ones on the disc: object; still ones around it: background)
// are hard labels, and cut the box down to the disc.
TEST(GrabCutSegmenter, PointPromptsCutALooseBoxDownToTheObject) {
  cv::Mat image(240, 320, CV_8UC1), disc_texture(240, 320, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(image, cv::RNG::UNIFORM, 60, 160);
  rng.fill(disc_texture, cv::RNG::UNIFORM, 70, 170);
  cv::Mat disc = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::circle(disc, {160, 120}, 40, cv::Scalar(255), cv::FILLED);
  disc_texture.copyTo(image, disc);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 1.5);
  const Box loose{160, 120, 150, 150};
  std::vector<PointPrompt> points;
  for (int y = 51; y < 190; y += 16)
    for (int x = 91; x < 230; x += 16) {
      const double r = std::hypot(x - 160.0, y - 120.0);
      if (r < 34) points.push_back({cv::Point2f(x, y), true});
      else if (r > 46) points.push_back({cv::Point2f(x, y), false});
    }
  GrabCutSegmenter s;
  const auto iou = [&](const cv::Mat& m) {
    return static_cast<double>(cv::countNonZero(m & disc)) / cv::countNonZero(m | disc);
  };
  const cv::Mat box_only = s.segment(image, {loose});
  const cv::Mat prompted = s.segmentWithPoints(image, {loose}, points);
  std::cout << "IoU with the disc: box alone " << iou(box_only) << ", with point prompts " << iou(prompted) << "\n";
  EXPECT_GT(iou(prompted), 0.8);
  EXPECT_GT(iou(prompted), iou(box_only) + 0.1);
  for (const PointPrompt& p : points)  // hard labels
    EXPECT_EQ(prompted.at<uint8_t>(cv::Point(p.pixel)), p.object ? 255 : 0) << p.pixel;
  // Points outside the box change nothing; without points the result is the box-only one.
  const cv::Mat far_points = s.segmentWithPoints(image, {loose}, {{cv::Point2f(5, 5), false}, {cv::Point2f(310, 230), true}});
  EXPECT_EQ(cv::countNonZero(far_points != box_only), 0);
  // A segmenter that cannot use points ignores them.
  FilledBoxSegmenter filled;
  EXPECT_EQ(cv::countNonZero(filled.segmentWithPoints(image, {loose}, points) != filled.segment(image, {loose})), 0);
}

// A grey image is segmented as its colour copy is (GrabCut downscales the grey region and makes
// only that colour): the same mask to the pixel, with and without point prompts, on a real frame
// (vtest.avi), for boxes inside, across the image's edge, and too small to model.
TEST(GrabCutSegmenter, AGreyImageGivesItsColourCopysMask) {
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  cv::VideoCapture video(test::kPedestrianVideo);
  cv::Mat frame, grey, colour;
  ASSERT_TRUE(video.read(frame));
  cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  const std::vector<Box> boxes = {Box{330, 300, 70, 160}, Box{20, 200, 60, 120}, Box{700, 60, 120, 90}, Box{400, 100, 8, 8}};
  std::vector<PointPrompt> points;
  for (int y = 230; y < 380; y += 12) points.push_back({cv::Point2f(330, y), true});
  for (int y = 230; y < 380; y += 12) points.push_back({cv::Point2f(298, y), false});
  GrabCutSegmenter s;
  const cv::Mat from_grey = s.segment(grey, boxes);
  EXPECT_GT(cv::countNonZero(from_grey), 0);
  EXPECT_EQ(cv::countNonZero(from_grey != s.segment(colour, boxes)), 0);
  const cv::Mat prompted_grey = s.segmentWithPoints(grey, boxes, points);
  EXPECT_EQ(cv::countNonZero(prompted_grey != s.segmentWithPoints(colour, boxes, points)), 0);
  EXPECT_GT(cv::countNonZero(prompted_grey != from_grey), 0);  // the points did change the cut
}

// A box's mask depends on the image and the box only: not on the calls before (GrabCut's k-means
// start draws from OpenCV's thread generator, which the segmenter starts from the same state on
// every call), so the order of the boxes does not matter and the caller's generator is untouched.
TEST(GrabCutSegmenter, ABoxsMaskDoesNotDependOnTheCallsBeforeIt) {
  ADUGS_REQUIRE_PEDESTRIAN_VIDEO();
  cv::VideoCapture video(test::kPedestrianVideo);
  cv::Mat frame;
  ASSERT_TRUE(video.read(frame));
  const Box walker{330, 300, 70, 160}, other{20, 200, 60, 120}, corner{700, 60, 120, 90};
  GrabCutSegmenter s;
  const cv::Mat first = s.segment(frame, {walker});
  EXPECT_GT(cv::countNonZero(first), 0);
  for (int k = 0; k < 3; ++k) s.segment(frame, {other, corner});  // the generator used in between
  EXPECT_EQ(cv::countNonZero(first != s.segment(frame, {walker})), 0);
  const cv::Mat forwards = s.segment(frame, {walker, other, corner});
  EXPECT_EQ(cv::countNonZero(forwards != s.segment(frame, {corner, other, walker})), 0);
  cv::theRNG().state = 42;
  s.segment(frame, {walker});
  EXPECT_EQ(cv::theRNG().state, 42u);
}

// On simulated street frames with their amodal ground-truth boxes, compare the segmented union
// with the exact dynamic mask (visible object pixels).
TEST(GrabCutSegmenter, SimulatedStreetMasksAgainstGroundTruth) {
  test::TempDir tmp("adugs_seg_sim");
  const auto street = test_support::makeSimulatedStreet(tmp.path(), 3.0);
  ASSERT_GE(street.image_names.size(), 60u);

  GrabCutSegmenter grabcut;
  FilledBoxSegmenter filled;
  double inter_g = 0, seg_g = 0, inter_f = 0, seg_f = 0, truth = 0;
  for (int f : {20, 40, 60}) {
    const cv::Mat image = cv::imread(street.imagePath(f), cv::IMREAD_GRAYSCALE);
    const cv::Mat mask = cv::imread(street.maskPath(f), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty());
    ASSERT_FALSE(mask.empty());
    const std::vector<Box> boxes = street.visibleBoxes(f, 0.2);
    const cv::Mat g = grabcut.segment(image, boxes), b = filled.segment(image, boxes);
    truth += cv::countNonZero(mask);
    inter_g += cv::countNonZero(g & mask);
    seg_g += cv::countNonZero(g);
    inter_f += cv::countNonZero(b & mask);
    seg_f += cv::countNonZero(b);
  }
  ASSERT_GT(truth, 1000);
  const double recall_g = inter_g / truth, precision_g = inter_g / seg_g;
  const double recall_f = inter_f / truth, precision_f = inter_f / seg_f;
  std::cout << "grabcut recall " << recall_g << " precision " << precision_g
            << "; filled boxes recall " << recall_f << " precision " << precision_f << "\n";
  EXPECT_GT(recall_g, 0.8);
  EXPECT_GT(precision_g, precision_f);
}

}  // namespace
}  // namespace adugs::tracking

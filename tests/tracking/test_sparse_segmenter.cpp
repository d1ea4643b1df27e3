// The sparse segmenter: a slow segmenter run every n-th frame (or when tracks appear or change
// shape), each track's mask carried by its tracked box in between.
#include <gtest/gtest.h>

#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "tests/test_support.h"
#include "tests/tracking/simulated_street.h"
#include "tracking/dynamic_masker.h"
#include "tracking/segment/grabcut_segmenter.h"
#include "tracking/segment/mask_refinement.h"
#include "tracking/segment/sparse_segmenter.h"

namespace adugs::tracking {
namespace {

// Masks the left half of every box (a shape the carried mask must keep) and counts its calls.
class HalfBoxSegmenter : public BoxSegmenter {
 public:
  explicit HalfBoxSegmenter(int* calls) : calls_(calls) {}
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override {
    ++*calls_;
    cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
    for (const Box& b : boxes) {
      Box left = b;
      left.w = b.w / 2;
      left.cx = b.left() + left.w / 2;
      const cv::Rect r = clippedRect(left, image.cols, image.rows);
      if (!r.empty()) mask(r).setTo(255);
    }
    return mask;
  }
  const char* name() const override { return "half"; }
  bool slow() const override { return true; }

 private:
  int* calls_;
};

TrackedObject object(int64_t id, const Box& box) { return {id, box, 0, true, 3, 0}; }

TEST(SparseSegmenter, CarriesEachTracksMaskWithItsBoxBetweenRuns) {
  int calls = 0;
  SparseSegmenter sparse(std::make_unique<HalfBoxSegmenter>(&calls), {5, 0.25, false});
  const cv::Mat image(200, 300, CV_8UC1, cv::Scalar(0));
  for (int f = 0; f < 12; ++f) {
    // Moves 4 px right per frame and grows 1 %: the carried mask follows, the left half stays.
    const Box box{100.0 + 4 * f, 100, 40 * (1 + 0.01 * f), 80 * (1 + 0.01 * f)};
    const cv::Mat mask = sparse.segment(image, {object(7, box)});
    EXPECT_EQ(mask.at<uint8_t>(static_cast<int>(box.cy), static_cast<int>(box.left() + 0.25 * box.w)), 255) << f;
    EXPECT_EQ(mask.at<uint8_t>(static_cast<int>(box.cy), static_cast<int>(box.left() + 0.75 * box.w)), 0) << f;
    EXPECT_NEAR(cv::countNonZero(mask), box.w * box.h / 2, 0.06 * box.w * box.h) << f;
  }
  EXPECT_EQ(calls, 3);  // frames 0, 5, 10
  EXPECT_EQ(sparse.innerRuns(), 3);
  // A new track is segmented at once; a box that changes shape too.
  sparse.segment(image, {object(7, {150, 100, 44, 88}), object(8, {50, 50, 20, 40})});
  EXPECT_EQ(calls, 4);
  sparse.segment(image, {object(7, {150, 100, 88, 88}), object(8, {50, 50, 20, 40})});
  EXPECT_EQ(calls, 5);
  // No objects: nothing to run.
  EXPECT_EQ(cv::countNonZero(sparse.segment(image, {})), 0);
  EXPECT_EQ(calls, 5);
}

TEST(SparseSegmenter, AsynchronousRunsDeliverOnALaterFrameAndFillTheBoxUntilThen) {
  int calls = 0;
  SparseSegmenter sparse(std::make_unique<HalfBoxSegmenter>(&calls), {100, 0.25, true});
  const cv::Mat image(200, 300, CV_8UC1, cv::Scalar(0));
  const Box box{150, 100, 40, 80};
  const cv::Mat first = sparse.segment(image, {object(1, box)});
  EXPECT_EQ(cv::countNonZero(first), 40 * 80) << "no mask yet: the whole box";
  cv::Mat later;
  for (int k = 0; k < 200 && (later.empty() || cv::countNonZero(later) == 40 * 80); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    later = sparse.segment(image, {object(1, box)});
  }
  EXPECT_EQ(cv::countNonZero(later), 20 * 80) << "the worker's half-box mask arrived";
  EXPECT_EQ(sparse.innerRuns(), 1);
}

// On the simulated street (GrabCut as the segmenter, every visible object detected), segmenting
// every 5th frame and carrying the masks costs little against every frame.
TEST(SparseSegmenter, EveryFifthFrameOnTheStreetKeepsTheMaskQuality) {
  test::TempDir tmp("adugs_sparse");
  const auto street = test_support::makeSimulatedStreet(tmp.path(), 4.0);
  const int frames = static_cast<int>(street.image_names.size());
  double covered[2] = {0, 0}, masked[2] = {0, 0}, truth = 0, correct[2] = {0, 0};
  int runs = 0;
  for (int k = 0; k < 2; ++k) {
    DynamicMaskerOptions options;
    options.segment_every = k == 0 ? 1 : 5;
    options.segment_async = false;
    DynamicMasker masker(options, std::make_unique<GrabCutSegmenter>());
    for (int f = 1; f <= frames; ++f) {
      const cv::Mat image = cv::imread(street.imagePath(f), cv::IMREAD_GRAYSCALE);
      std::vector<Detection> dets;
      for (const Box& b : street.visibleBoxes(f, 0.4)) dets.push_back({b, 0});
      const DynamicMaskResult r = masker.process(image, dets);
      if (f <= 10) continue;
      const cv::Mat exact = cv::imread(street.maskPath(f), cv::IMREAD_GRAYSCALE);
      if (k == 0) truth += cv::countNonZero(exact);
      covered[k] += cv::countNonZero(exact & r.mask);
      masked[k] += cv::countNonZero(r.mask);
      correct[k] += cv::countNonZero(exact & r.mask);
    }
    if (k == 1) runs = masker.segmenterRuns();
  }
  ASSERT_GT(truth, 10000);
  const double recall[2] = {covered[0] / truth, covered[1] / truth};
  const double precision[2] = {correct[0] / masked[0], correct[1] / masked[1]};
  std::cout << "GrabCut every frame: recall " << recall[0] << ", precision " << precision[0]
            << "; every 5th frame, carried: recall " << recall[1] << ", precision " << precision[1] << ", "
            << runs << " runs for " << frames << " frames\n";
  EXPECT_LT(runs, frames / 2);
  EXPECT_GT(recall[1], recall[0] - 0.05);
  EXPECT_GT(precision[1], precision[0] - 0.1);
}

}  // namespace
}  // namespace adugs::tracking

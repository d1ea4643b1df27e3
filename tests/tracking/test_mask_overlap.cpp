// The pixel counts behind the masks' recall and precision (tracking/eval/mask_overlap.h): a
// hand-worked case, and random masks and boxes against OpenCV's whole-image operations (how the
// masking stage counted before, 2026-12-05).
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "tracking/eval/mask_overlap.h"

namespace adugs::tracking {
namespace mask_overlap_test {

TEST(MaskOverlap, HandWorkedTwoOverlappingBoxes) {
  // Exact: columns 0-3 of a 10 x 4 image (16 px); mask: columns 2-5 (16 px); both: columns 2-3.
  cv::Mat exact = cv::Mat::zeros(4, 10, CV_8UC1), mask = exact.clone();
  exact.colRange(0, 4).setTo(255);
  mask.colRange(2, 6).setTo(1);  // any nonzero value is in
  const MaskOverlap whole = maskOverlap(exact, mask);
  EXPECT_EQ(whole.exact, 16);
  EXPECT_EQ(whole.masked, 16);
  EXPECT_EQ(whole.covered, 8);
  // Boxes x 1-2 and x 2-4 over rows 0-1, overlapping at x 2: their union is x 1-4, rows 0-1
  // (8 px, x 2 counted once): exact x 1-3 (6), masked x 2-4 (6), both x 2-3 (4).
  // A box outside the image and an empty one add nothing.
  const MaskOverlap in = maskOverlapInBoxes(exact, mask, {cv::Rect(1, 0, 2, 2), cv::Rect(2, 0, 3, 2),
                                                          cv::Rect(20, 20, 5, 5), cv::Rect(0, 0, 0, 3)});
  EXPECT_EQ(in.exact, 6);
  EXPECT_EQ(in.masked, 6);
  EXPECT_EQ(in.covered, 4);
  EXPECT_EQ(maskOverlapInBoxes(exact, mask, {}).exact, 0);
  EXPECT_THROW(maskOverlap(exact, cv::Mat::zeros(4, 9, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(maskOverlap(exact, cv::Mat::zeros(4, 10, CV_16UC1)), std::invalid_argument);
}

TEST(MaskOverlap, SameCountsAsWholeImageOperationsOnRandomMasks) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> x(-40, 760), y(-40, 490), side(0, 200), count(0, 5);
  for (int trial = 0; trial < 40; ++trial) {
    cv::Mat exact = cv::Mat::zeros(480, 752, CV_8UC1), mask = exact.clone();
    for (int k = count(rng); k > 0; --k) cv::ellipse(exact, {x(rng), y(rng)}, {side(rng), side(rng)}, 0, 0, 360, 255, -1);
    for (int k = count(rng); k > 0; --k) cv::rectangle(mask, cv::Rect(x(rng), y(rng), side(rng), side(rng)), 255, -1);
    std::vector<cv::Rect> boxes;
    cv::Mat area = cv::Mat::zeros(exact.size(), CV_8UC1);
    for (int k = count(rng); k > 0; --k) {
      boxes.emplace_back(x(rng), y(rng), side(rng), side(rng));
      area(boxes.back() & cv::Rect(0, 0, 752, 480)).setTo(255);
    }
    const MaskOverlap whole = maskOverlap(exact, mask);
    EXPECT_EQ(whole.exact, cv::countNonZero(exact));
    EXPECT_EQ(whole.masked, cv::countNonZero(mask));
    EXPECT_EQ(whole.covered, cv::countNonZero(exact & mask));
    const MaskOverlap in = maskOverlapInBoxes(exact, mask, boxes);
    EXPECT_EQ(in.exact, cv::countNonZero(exact & area)) << "trial " << trial;
    EXPECT_EQ(in.masked, cv::countNonZero(mask & area)) << "trial " << trial;
    EXPECT_EQ(in.covered, cv::countNonZero(exact & mask & area)) << "trial " << trial;
  }
}

}  // namespace mask_overlap_test
}  // namespace adugs::tracking

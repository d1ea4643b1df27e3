#include "tracking/segment/mask_refinement.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace adugs::tracking {
namespace {

TEST(DiskElement, HandWorkedRadiusOneAndTwo) {
  cv::Mat d1 = diskElement(1);
  const uint8_t expect1[9] = {0, 1, 0, 1, 1, 1, 0, 1, 0};
  ASSERT_EQ(d1.rows, 3);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(d1.data[i], expect1[i]) << i;
  cv::Mat d2 = diskElement(2);
  ASSERT_EQ(d2.rows, 5);
  EXPECT_EQ(cv::countNonZero(d2), 13);  // x^2 + y^2 <= 4: 5 + 2*3 + 2
  EXPECT_EQ(d2.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(d2.at<uint8_t>(0, 2), 1);
  EXPECT_EQ(d2.at<uint8_t>(1, 1), 1);
}

TEST(RefineDynamicMask, RemovesSpeckleAndGrowsObjectByDilateMinusErode) {
  cv::Mat mask(60, 80, CV_8UC1, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(20, 20, 21, 11), cv::Scalar(255), cv::FILLED);  // object
  mask.at<uint8_t>(5, 5) = 255;                                                // speckle
  MaskRefinementOptions opt;
  opt.erode_radius_px = 1;
  opt.dilate_radius_px = 3;
  cv::Mat out = refineDynamicMask(mask, opt);
  EXPECT_EQ(out.at<uint8_t>(5, 5), 0) << "isolated pixel must be eroded away";
  // Rectangle x in [20,40]: erosion by 1 -> [21,39], dilation by 3 -> [18,42] on the middle row.
  const int row = 25;
  EXPECT_EQ(out.at<uint8_t>(row, 18), 255);
  EXPECT_EQ(out.at<uint8_t>(row, 17), 0);
  EXPECT_EQ(out.at<uint8_t>(row, 42), 255);
  EXPECT_EQ(out.at<uint8_t>(row, 43), 0);
  // Corners get rounded by the disk: (18,18) is sqrt(3^2+3^2) > 3 from the eroded corner (21,21).
  EXPECT_EQ(out.at<uint8_t>(18, 18), 0);
  EXPECT_EQ(out.at<uint8_t>(18, 21), 255);
}

TEST(RefineDynamicMask, ObjectTouchingImageBorderIsNotErodedFromTheBorder) {
  cv::Mat mask(40, 40, CV_8UC1, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(0, 10, 10, 10), cv::Scalar(255), cv::FILLED);
  cv::Mat out = refineDynamicMask(mask, {2, 4});
  EXPECT_EQ(out.at<uint8_t>(15, 0), 255);
}

// The refinement works only around the masked pixels; the result must be the whole image's
// erosion then dilation, for objects inside, near and on the image's edges, apart or together.
TEST(RefineDynamicMask, SameAsTheWholeImagesMorphology) {
  cv::RNG rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    cv::Mat mask(48, 64, CV_8UC1, cv::Scalar(0));
    const int objects = trial % 4;  // 0: nothing masked
    for (int k = 0; k < objects; ++k) {
      const cv::Point c(rng.uniform(-4, 68), rng.uniform(-4, 52));
      cv::ellipse(mask, c, cv::Size(rng.uniform(1, 12), rng.uniform(1, 9)), rng.uniform(0, 180), 0,
                  360, cv::Scalar(255), cv::FILLED);
    }
    if (trial % 5 == 0) mask.at<uint8_t>(rng.uniform(0, 48), rng.uniform(0, 64)) = 200;  // speckle
    const MaskRefinementOptions opt{trial % 3, 3 + trial % 5};
    cv::Mat eroded, expected;
    if (opt.erode_radius_px > 0)
      cv::erode(mask > 0, eroded, diskElement(opt.erode_radius_px));
    else
      eroded = mask > 0;
    cv::dilate(eroded, expected, diskElement(opt.dilate_radius_px));
    const cv::Mat out = refineDynamicMask(mask, opt);
    ASSERT_EQ(out.size(), mask.size());
    EXPECT_EQ(cv::countNonZero(out != expected), 0) << "trial " << trial;
  }
}

TEST(RefineDynamicMask, RejectsBadInput) {
  EXPECT_THROW(refineDynamicMask(cv::Mat(), {}), std::invalid_argument);
  EXPECT_THROW(refineDynamicMask(cv::Mat(10, 10, CV_32FC1), {}), std::invalid_argument);
  EXPECT_THROW(refineDynamicMask(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), {3, 3}),
               std::invalid_argument);
}

}  // namespace
}  // namespace adugs::tracking

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

TEST(RefineDynamicMask, RejectsBadInput) {
  EXPECT_THROW(refineDynamicMask(cv::Mat(), {}), std::invalid_argument);
  EXPECT_THROW(refineDynamicMask(cv::Mat(10, 10, CV_32FC1), {}), std::invalid_argument);
  EXPECT_THROW(refineDynamicMask(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), {3, 3}),
               std::invalid_argument);
}

}  // namespace
}  // namespace adugs::tracking

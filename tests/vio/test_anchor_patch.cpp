// AnchorPatch: affine inverse-compositional alignment of a feature's first-seen patch.
#include <gtest/gtest.h>

#include <cmath>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "vio/frontend/anchor_patch.h"

namespace adugs::vio {
namespace {

// Smooth random texture (blobs a few pixels wide), like a rendered surface.
cv::Mat texture(int seed) {
  cv::Mat coarse(40, 60, CV_32F);
  cv::RNG rng(seed);
  rng.fill(coarse, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::Mat fine, out;
  cv::resize(coarse, fine, cv::Size(480, 320), 0, 0, cv::INTER_CUBIC);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 1.5);
  fine.convertTo(out, CV_8U);
  return out;
}

// The image seen after the patch around c0 moved by x1 = A (x0 - c0) + t.
cv::Mat warped(const cv::Mat& image, const Eigen::Vector2d& c0, const Eigen::Matrix2d& A,
               const Eigen::Vector2d& t, double gain = 1.0, double offset = 0.0) {
  const Eigen::Vector2d b = t - A * c0;
  const cv::Mat M = (cv::Mat_<double>(2, 3) << A(0, 0), A(0, 1), b.x(), A(1, 0), A(1, 1), b.y());
  cv::Mat out;
  cv::warpAffine(image, out, M, image.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  out.convertTo(out, CV_8U, gain, offset);
  return out;
}

Eigen::Matrix2d similarity(double scale, double angle_deg) {
  return scale * Eigen::Rotation2Dd(angle_deg * M_PI / 180.0).toRotationMatrix();
}

TEST(AnchorPatch, RecoversAKnownAffineWarpFromAKltLikeStart) {
  const cv::Mat image = texture(1);
  const Eigen::Vector2d c0(200.0, 150.0);
  const AnchorPatch patch(image, c0, 8);
  ASSERT_TRUE(patch.valid());
  Eigen::Matrix2d A = similarity(1.15, 8.0);
  A(0, 1) += 0.05;  // a little shear: not a similarity
  const Eigen::Vector2d t(203.3, 147.6);
  const cv::Mat next = warped(image, c0, A, t);
  // KLT would hand over a position within a few tenths of a pixel and no shape.
  const AnchorPatch::Result r =
      patch.align(next, Eigen::Matrix2d::Identity(), t + Eigen::Vector2d(0.4, -0.3));
  ASSERT_TRUE(r.converged);
  EXPECT_LT((r.position - t).norm(), 0.05) << r.position.transpose();
  EXPECT_LT((r.A - A).norm(), 0.02) << r.A;
  EXPECT_GT(r.zncc, 0.99);
}

TEST(AnchorPatch, ExposureChangeDoesNotMoveTheFit) {
  const cv::Mat image = texture(2);
  const Eigen::Vector2d c0(240.3, 160.7);  // sub-pixel anchor
  const AnchorPatch patch(image, c0, 8);
  ASSERT_TRUE(patch.valid());
  const Eigen::Matrix2d A = similarity(0.9, -5.0);
  const Eigen::Vector2d t(236.8, 163.1);
  const cv::Mat darker = warped(image, c0, A, t, 0.6, 25.0);
  const AnchorPatch::Result r = patch.align(darker, Eigen::Matrix2d::Identity(), t);
  ASSERT_TRUE(r.converged);
  EXPECT_LT((r.position - t).norm(), 0.05) << r.position.transpose();
  EXPECT_GT(r.zncc, 0.98);
}

TEST(AnchorPatch, FlatOrEdgeOnlyPatchesAreNotAnchors) {
  const cv::Mat flat(100, 100, CV_8U, cv::Scalar(128));
  EXPECT_FALSE(AnchorPatch(flat, {50, 50}, 8).valid());
  // A straight vertical edge fixes x but not y (nor shear along it).
  cv::Mat edge(100, 100, CV_8U, cv::Scalar(40));
  edge.colRange(50, 100).setTo(200);
  cv::GaussianBlur(edge, edge, cv::Size(0, 0), 1.0);
  EXPECT_FALSE(AnchorPatch(edge, {50, 50}, 8).valid());
  // Too close to the border for the patch.
  EXPECT_FALSE(AnchorPatch(texture(3), {5, 50}, 8).valid());
}

TEST(AnchorPatch, AWarpLeavingTheImageDoesNotConverge) {
  const cv::Mat image = texture(4);
  const AnchorPatch patch(image, {200, 150}, 8);
  ASSERT_TRUE(patch.valid());
  const AnchorPatch::Result r = patch.align(image, Eigen::Matrix2d::Identity(), {3.0, 150.0});
  EXPECT_FALSE(r.converged);
}

}  // namespace
}  // namespace adugs::vio

// The start of the intrinsic calibration: focal candidates from the board's vanishing points,
// their score, and that the start stays inside the plausible range where a plain homography
// estimate runs away (issue 18: "initial focal 8106.3 px" on near-still views).
#include "calib/intrinsics/intrinsics_start.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "tests/calib/camera_imu_synthetic.h"
#include "tests/calib/synthetic_views.h"

namespace adugs::calib {
namespace {

// H = K [r1 r2 t] with K = diag(f, f, 1): both pairs of vanishing points give f back.
TEST(IntrinsicsStart, FocalFromTheVanishingPointsOfATiltedBoard) {
  const double f = 460;
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  Eigen::Matrix3d H;
  H.col(0) = R.col(0);
  H.col(1) = R.col(1);
  H.col(2) = Eigen::Vector3d(0.1, -0.05, 1.2);
  H = Eigen::DiagonalMatrix<double, 3>(f, f, 1) * H;
  H *= 3.7;  // any scale
  const std::vector<double> c = focalCandidatesFromHomography(H);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0], f, 1e-9 * f);
  EXPECT_NEAR(c[1], f, 1e-9 * f);
  // Face-on (R = I): the vanishing points are at infinity, no candidate.
  Eigen::Matrix3d face_on = Eigen::Matrix3d::Identity();
  face_on(2, 2) = 1.1;
  EXPECT_TRUE(focalCandidatesFromHomography(Eigen::DiagonalMatrix<double, 3>(f, f, 1) * face_on).empty());
}

// Distortion-free views: the score is lowest at the true focal length, and the start finds it.
TEST(IntrinsicsStart, ScoreIsLowestAtTheTrueFocal) {
  CalibCamera cam = synth::eurocLikeCamera();
  cam.params = {460, 460, 375.5, 239.5, 0, 0, 0, 0};
  const auto views = synth::syntheticViews(cam, AprilGrid{}, 12, 0.2, 5);
  std::vector<const TargetObservation*> v;
  for (const auto& x : views) v.push_back(&x);
  const double at_truth = scoreFocal(v, cam.model, 460, 375.5, 239.5);
  EXPECT_LT(at_truth, 0.35);  // the 0.2 px noise
  EXPECT_GT(scoreFocal(v, cam.model, 400, 375.5, 239.5), 2 * at_truth);
  EXPECT_GT(scoreFocal(v, cam.model, 530, 375.5, 239.5), 2 * at_truth);
  const FocalStart s = findFocalStart(v, 752, 480, cam.model);
  EXPECT_NEAR(s.focal_px, 460, 0.01 * 460);
  EXPECT_GT(s.view_candidates, 12);
  EXPECT_EQ(s.views_scored, 12);
}

// A camera held still, board face-on: the homography says 6000-9800 px (the old start; issue
// 18 saw 8106 px), the start never leaves [0.2, 5] x width.
TEST(IntrinsicsStart, NearStillFaceOnViewsStayInThePlausibleRange) {
  const CalibCamera cam = synth::eurocLikeCamera();
  for (unsigned seed = 1; seed <= 2; ++seed) {
    const auto views = synth::nearStillViews(cam, synth::eurocGrid(), 30, 0.2, seed, 1.1, 0, 0.002, 0.1);
    std::vector<const TargetObservation*> v;
    std::vector<double> raw;  // the per-view estimates, unfiltered
    for (const auto& x : views) {
      v.push_back(&x);
      std::vector<cv::Point2d> src, dst;
      for (const auto& c : x.corners) {
        src.emplace_back(c.point.x(), c.point.y());
        dst.emplace_back(c.pixel.x() - 375.5, c.pixel.y() - 239.5);
      }
      Eigen::Matrix3d H;
      cv::cv2eigen(cv::findHomography(src, dst, 0), H);
      for (double f : focalCandidatesFromHomography(H)) raw.push_back(f);
    }
    std::nth_element(raw.begin(), raw.begin() + raw.size() / 2, raw.end());
    EXPECT_GT(raw[raw.size() / 2], 5 * 752) << "the failure mode: the views' own estimate runs away";
    const FocalStart s = findFocalStart(v, 752, 480, cam.model);
    EXPECT_GE(s.focal_px, 0.2 * 752);
    EXPECT_LE(s.focal_px, 5 * 752);
    EXPECT_TRUE(std::isfinite(s.score_px));
  }
  EXPECT_THROW(findFocalStart({}, 752, 480, cam.model), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::calib

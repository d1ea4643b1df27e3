// CameraModel: hand-worked radtan value, agreement with OpenCV's projection functions, and
// pixel -> normalised -> pixel round trips over the whole image for both distortion models.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "vio/camera_model.h"

namespace adugs::vio {
namespace {

// EuRoC cam0 (V1_01 sensor.yaml).
CameraModel eurocCam0() {
  return CameraModel(752, 480, 458.654, 457.296, 367.215, 248.375,
                     CameraModel::Distortion::kRadialTangential,
                     {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

// TUM-VI cam0 (512x512 equidistant/Kannala-Brandt), a strongly distorting fisheye.
CameraModel tumviCam0() {
  return CameraModel(512, 512, 190.97847715128717, 190.9733070521226, 254.93170605935475,
                     256.8974428996504, CameraModel::Distortion::kEquidistant,
                     {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
                      0.00020293673591811182});
}

TEST(CameraModel, RadtanHandWorkedValue) {
  // xn = (0.1, -0.2): r2 = 0.05, radial = 1 + k1 r2 + k2 r2^2 = 0.986014492175
  // xd = 0.1 radial + 2 p1 x y + p2 (r2 + 2 x^2)      = 0.0986014492175 - 7.7436e-6 + 1.2333098e-6
  //    = 0.0985949389273
  // yd = -0.2 radial + p1 (r2 + 2 y^2) + 2 p2 x y     = -0.197202898435 + 2.51667e-5 - 7.047485e-7
  //    = -0.1971784364835
  // u = fx xd + cx = 412.435963119, v = fy yd + cy = 158.20608971
  const CameraModel cam = eurocCam0();
  const Eigen::Vector2d xd = cam.distort({0.1, -0.2});
  EXPECT_NEAR(xd.x(), 0.0985949389273, 1e-12);
  EXPECT_NEAR(xd.y(), -0.1971784364835, 1e-12);
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({0.2, -0.4, 2.0}, &uv));
  EXPECT_NEAR(uv.x(), 412.435963119, 1e-6);
  EXPECT_NEAR(uv.y(), 158.20608971, 1e-6);
  EXPECT_FALSE(cam.project({0.2, -0.4, -1.0}, &uv));
}

TEST(CameraModel, AgreesWithOpenCvProjection) {
  const std::vector<cv::Point3d> pts = {{0.1, -0.2, 1.0}, {-0.5, 0.3, 1.0}, {0.6, 0.45, 1.2}};
  for (const CameraModel& cam : {eurocCam0(), tumviCam0()}) {
    std::vector<cv::Point2d> ref;
    if (cam.distortion() == CameraModel::Distortion::kEquidistant) {
      cv::fisheye::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                                 cam.cameraMatrix(), cam.distortionCoeffs());
    } else {
      cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam.cameraMatrix(),
                        cam.distortionCoeffs(), ref);
    }
    for (size_t i = 0; i < pts.size(); ++i) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.project({pts[i].x, pts[i].y, pts[i].z}, &uv));
      EXPECT_NEAR(uv.x(), ref[i].x, 1e-6);
      EXPECT_NEAR(uv.y(), ref[i].y, 1e-6);
    }
  }
}

// Every 4th pixel including the corners: undistort then distort back to within 1e-10 normalised.
// Fisheye pixels whose ray is 85 degrees or more off-axis have no (finite) normalised coordinates
// and are skipped; they are the black corners outside TUM-VI's image circle.
void expectRoundTrip(const CameraModel& cam, double min_fraction_tested) {
  const double max_tan = std::tan(85.0 * M_PI / 180.0);
  double worst = 0;
  int tested = 0, total = 0;
  for (int v = 0; v <= cam.height(); v += 4) {
    for (int u = 0; u <= cam.width(); u += 4) {
      const Eigen::Vector2d uv(std::min(u, cam.width() - 1), std::min(v, cam.height() - 1));
      const Eigen::Vector2d xn = cam.pixelToNormalized(uv);
      const Eigen::Vector2d xd((uv.x() - cam.cx()) / cam.fx(), (uv.y() - cam.cy()) / cam.fy());
      ++total;
      if (!(xn.norm() < max_tan)) continue;
      ++tested;
      worst = std::max(worst, (cam.distort(xn) - xd).norm());
    }
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_GE(tested, min_fraction_tested * total);
}

TEST(CameraModel, RoundTripOverImageRadtan) { expectRoundTrip(eurocCam0(), 1.0); }
TEST(CameraModel, RoundTripOverImageEquidistant) { expectRoundTrip(tumviCam0(), 0.75); }

TEST(CameraModel, UndistortedPointsMatchOpenCv) {
  const CameraModel cam = eurocCam0();
  const std::vector<cv::Point2f> px = {{0, 0}, {751, 479}, {367, 248}, {100, 400}};
  std::vector<cv::Point2f> ref;
  cv::undistortPoints(px, ref, cam.cameraMatrix(), cam.distortionCoeffs(), cv::noArray(),
                      cv::noArray(), cv::TermCriteria(cv::TermCriteria::COUNT, 100, 0));
  std::vector<Eigen::Vector2d> xn;
  cam.pixelsToNormalized(px, &xn);
  for (size_t i = 0; i < px.size(); ++i) {
    EXPECT_NEAR(xn[i].x(), ref[i].x, 1e-5);  // float output on OpenCV's side
    EXPECT_NEAR(xn[i].y(), ref[i].y, 1e-5);
  }
}

TEST(CameraModel, JacobianMatchesFiniteDifferences) {
  for (const CameraModel& cam : {eurocCam0(), tumviCam0()}) {
    const Eigen::Vector2d x(0.37, -0.21);
    Eigen::Matrix2d J;
    cam.distort(x, &J);
    const double h = 1e-7;
    for (int c = 0; c < 2; ++c) {
      Eigen::Vector2d dx = Eigen::Vector2d::Zero();
      dx[c] = h;
      const Eigen::Vector2d col = (cam.distort(x + dx) - cam.distort(x - dx)) / (2 * h);
      EXPECT_NEAR((col - J.col(c)).norm(), 0.0, 1e-7);
    }
  }
}

TEST(CameraModel, FromEurocCalibration) {
  data::CameraCalibration c;
  c.width = 752;
  c.height = 480;
  c.fx = 458.654;
  c.fy = 457.296;
  c.cx = 367.215;
  c.cy = 248.375;
  c.distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  const CameraModel cam(c);
  EXPECT_EQ(cam.distortion(), CameraModel::Distortion::kRadialTangential);
  EXPECT_NEAR((cam.distort({0.1, -0.2}) - eurocCam0().distort({0.1, -0.2})).norm(), 0, 1e-15);
  c.distortion.pop_back();
  EXPECT_THROW(CameraModel{c}, std::invalid_argument);
  EXPECT_THROW(CameraModel(0, 480, 1, 1, 0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio

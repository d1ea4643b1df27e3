#include "calib/camera_model.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "tests/calib/synthetic_views.h"

namespace adugs::calib {
namespace {

// Our projection must equal OpenCV's for both models (OpenCV's fisheye model is Kalibr's
// equidistant model).
TEST(CameraModel, MatchesOpenCvRadtanAndFisheye) {
  const std::vector<cv::Point3d> pts = {{0.1, -0.2, 1.0}, {-0.5, 0.3, 0.8}, {0.0, 0.0, 2.0},
                                        {0.9, 0.7, 1.1}, {1e-9, 0, 1.0}};
  const cv::Mat rvec = cv::Mat::zeros(3, 1, CV_64F), tvec = cv::Mat::zeros(3, 1, CV_64F);
  for (const PinholeCamera& cam : {synth::eurocLikeCamera(), synth::fisheyeCamera()}) {
    const auto& p = cam.params;
    const cv::Mat K = (cv::Mat_<double>(3, 3) << p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
    const cv::Mat D = (cv::Mat_<double>(1, 4) << p[4], p[5], p[6], p[7]);
    std::vector<cv::Point2d> expected;
    if (cam.model == DistortionModel::kRadialTangential)
      cv::projectPoints(pts, rvec, tvec, K, D, expected);
    else
      cv::fisheye::projectPoints(pts, expected, rvec, tvec, K, D);
    for (size_t i = 0; i < pts.size(); ++i) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.project({pts[i].x, pts[i].y, pts[i].z}, uv));
      EXPECT_NEAR(uv.x(), expected[i].x, 1e-6) << kalibrName(cam.model) << " point " << i;
      EXPECT_NEAR(uv.y(), expected[i].y, 1e-6) << kalibrName(cam.model) << " point " << i;
    }
  }
}

TEST(CameraModel, UnprojectInvertsProject) {
  for (const PinholeCamera& cam : {synth::eurocLikeCamera(), synth::fisheyeCamera()}) {
    for (double u = 10; u < cam.width; u += 97)
      for (double v = 10; v < cam.height; v += 83) {
        // The fisheye's image corners lie beyond 90 degrees: no point on the z = 1 plane.
        if (std::hypot(u - cam.pu(), v - cam.pv()) > 0.5 * std::min(cam.width, cam.height) - 20)
          continue;
        Eigen::Vector3d ray;
        ASSERT_TRUE(cam.unproject({u, v}, ray)) << kalibrName(cam.model) << " " << u << "," << v;
        Eigen::Vector2d uv;
        ASSERT_TRUE(cam.project(ray, uv));
        EXPECT_NEAR(uv.x(), u, 1e-6);
        EXPECT_NEAR(uv.y(), v, 1e-6);
      }
  }
}

TEST(CameraModel, BehindTheCameraDoesNotProject) {
  Eigen::Vector2d uv;
  EXPECT_FALSE(synth::eurocLikeCamera().project({0, 0, -1}, uv));
}

TEST(CameraModel, DistortionModelNames) {
  DistortionModel m;
  EXPECT_TRUE(parseDistortionModel("radtan", m));
  EXPECT_EQ(m, DistortionModel::kRadialTangential);
  EXPECT_TRUE(parseDistortionModel("radial-tangential", m));
  EXPECT_TRUE(parseDistortionModel("equidistant", m));
  EXPECT_EQ(m, DistortionModel::kEquidistant);
  EXPECT_TRUE(parseDistortionModel("equi", m));
  EXPECT_FALSE(parseDistortionModel("fov", m));
  EXPECT_FALSE(parseDistortionModel("Radtan", m));
  EXPECT_EQ(kalibrName(DistortionModel::kEquidistant), "equidistant");
}

}  // namespace
}  // namespace adugs::calib

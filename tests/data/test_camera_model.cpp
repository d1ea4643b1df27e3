// The product's one camera model (data/camera_model.h), for both distortion models: a hand-worked
// radtan value, agreement with OpenCV's projection and undistortion, pixel <-> normalised and
// pixel -> ray -> pixel round trips over whole images, the analytic Jacobian against finite
// differences and against Ceres' autodiff of the template, the templates against the class, the
// model names, and the simulator's camera description (SimCamera) on top of it.
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "data/camera_model.h"
#include "data/input_error.h"
#include "data/sim/sim_camera.h"
#include "tests/test_support.h"

namespace adugs::data {
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

// A T265-like fisheye (848x800) whose k2..k4 are larger than TUM-VI's.
CameraModel t265Cam() {
  return CameraModel(848, 800, 286.18, 286.39, 416.94, 403.27,
                     CameraModel::Distortion::kEquidistant, {-0.0029, 0.0379, -0.0367, 0.0066});
}

std::vector<CameraModel> distortedCameras() { return {eurocCam0(), tumviCam0(), t265Cam()}; }

DistortionModel modelOf(const CameraModel& cam) {
  return cam.distortion() == CameraModel::Distortion::kEquidistant
             ? DistortionModel::kEquidistant
             : DistortionModel::kRadialTangential;
}

std::string nameOf(const CameraModel& cam) {
  return kalibrName(modelOf(cam)) + " " + std::to_string(cam.width());
}

using test::paramsOf;

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
}

TEST(CameraModel, BehindTheCameraDoesNotProject) {
  for (const CameraModel& cam : distortedCameras()) {
    Eigen::Vector2d uv(-7, -7);
    EXPECT_FALSE(cam.project({0.2, -0.4, -1.0}, &uv)) << nameOf(cam);
    EXPECT_FALSE(cam.project({0, 0, 0}, &uv)) << nameOf(cam);
    EXPECT_EQ(uv, Eigen::Vector2d(-7, -7));  // untouched
    const std::array<double, 8> params = paramsOf(cam);
    const double p_C[3] = {0, 0, -1};
    EXPECT_FALSE(projectPoint(modelOf(cam), params.data(), p_C, uv.data())) << nameOf(cam);
  }
}

// OpenCV's plumb-bob (first four coefficients) is radtan; its fisheye model is equidistant.
TEST(CameraModel, AgreesWithOpenCvProjection) {
  const std::vector<cv::Point3d> pts = {{0.1, -0.2, 1.0}, {-0.5, 0.3, 1.0}, {0.6, 0.45, 1.2},
                                        {-0.5, 0.3, 0.8}, {0.0, 0.0, 2.0},  {0.9, 0.7, 1.1},
                                        {1e-9, 0, 1.0}};
  for (const CameraModel& cam : distortedCameras()) {
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
      EXPECT_NEAR(uv.x(), ref[i].x, 1e-6) << nameOf(cam) << " point " << i;
      EXPECT_NEAR(uv.y(), ref[i].y, 1e-6) << nameOf(cam) << " point " << i;
    }
  }
}

TEST(CameraModel, UndistortedPointsMatchOpenCv) {
  {
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
  for (const CameraModel& cam : {tumviCam0(), t265Cam()}) {
    // Within the image circle (up to ~75 degrees off-axis).
    const double c = cam.cx(), r = 0.8 * cam.cx();
    const std::vector<cv::Point2d> px = {{c, cam.cy()},
                                         {c + r, cam.cy()},
                                         {c - 0.5 * r, cam.cy() + 0.6 * r},
                                         {c - 0.4 * r, cam.cy() - 0.7 * r}};
    std::vector<cv::Point2d> ref;
    cv::fisheye::undistortPoints(
        px, ref, cam.cameraMatrix(), cam.distortionCoeffs(), cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-15));
    for (size_t i = 0; i < px.size(); ++i) {
      const Eigen::Vector2d xn = cam.pixelToNormalized({px[i].x, px[i].y});
      EXPECT_NEAR(xn.x(), ref[i].x, 1e-8) << nameOf(cam) << " point " << i;
      EXPECT_NEAR(xn.y(), ref[i].y, 1e-8) << nameOf(cam) << " point " << i;
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
  EXPECT_LT(worst, 1e-10) << nameOf(cam);
  EXPECT_GE(tested, min_fraction_tested * total) << nameOf(cam);
}

TEST(CameraModel, RoundTripOverImageRadtan) { expectRoundTrip(eurocCam0(), 1.0); }
TEST(CameraModel, RoundTripOverImageEquidistant) {
  expectRoundTrip(tumviCam0(), 0.75);
  expectRoundTrip(t265Cam(), 0.7);  // a smaller image circle
}

// Pixel -> ray -> a point along it -> pixel, on a grid over the image (the sub-pixel offsets keep
// it off the pixel centres); fisheye pixels beyond 85 degrees are skipped as above.
TEST(CameraModel, UnprojectThenProjectReturnsThePixel) {
  const double max_tan = std::tan(85.0 * M_PI / 180.0);
  for (const CameraModel& cam : distortedCameras()) {
    int tested = 0;
    double worst = 0;
    for (double u = 0; u < cam.width(); u += 37.5)
      for (double v = 0; v < cam.height(); v += 29.5) {
        const Eigen::Vector3d ray = cam.unproject({u, v});
        EXPECT_EQ(ray.z(), 1.0);
        if (!(ray.head<2>().norm() < max_tan)) continue;
        Eigen::Vector2d uv;
        ASSERT_TRUE(cam.project(ray * 2.5, &uv)) << nameOf(cam);
        worst = std::max(worst, (uv - Eigen::Vector2d(u, v)).norm());
        ++tested;
      }
    EXPECT_LT(worst, 1e-8) << nameOf(cam) << " pixels";
    EXPECT_GT(tested, 150) << nameOf(cam);
  }
}

// Fisheye rays at or beyond 90 degrees have no point on the z = 1 plane: undistortion stops just
// short of 90 degrees, pointing the right way.
TEST(CameraModel, FisheyeBeyondNinetyDegreesStopsShortOfIt) {
  const CameraModel cam = tumviCam0();
  const Eigen::Vector2d corner(0, 0);
  const Eigen::Vector2d xn = cam.pixelToNormalized(corner);
  EXPECT_TRUE(xn.allFinite());
  EXPECT_GT(std::atan(xn.norm()), 0.5 * M_PI - 1e-6);
  const Eigen::Vector2d xd((corner.x() - cam.cx()) / cam.fx(), (corner.y() - cam.cy()) / cam.fy());
  EXPECT_GT(xn.normalized().dot(xd.normalized()), 1 - 1e-12);
}

TEST(CameraModel, JacobianMatchesFiniteDifferences) {
  for (const CameraModel& cam : distortedCameras()) {
    for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.37, -0.21), Eigen::Vector2d(-1.4, 0.9),
                                     Eigen::Vector2d(1e-4, 2e-4), Eigen::Vector2d(3.0, 4.0)}) {
      Eigen::Matrix2d J;
      cam.distort(x, &J);
      const double h = 1e-7 * std::max(1.0, x.norm());
      for (int c = 0; c < 2; ++c) {
        Eigen::Vector2d dx = Eigen::Vector2d::Zero();
        dx[c] = h;
        const Eigen::Vector2d col = (cam.distort(x + dx) - cam.distort(x - dx)) / (2 * h);
        EXPECT_NEAR((col - J.col(c)).norm(), 0.0, 1e-7 * std::max(1.0, J.norm()))
            << nameOf(cam) << " at " << x.transpose();
      }
    }
  }
}

// The calibration differentiates distortPoint with Ceres' jets; the front-end uses the class's
// analytic Jacobian. They must be the same derivative of the same function.
TEST(CameraModel, AnalyticJacobianMatchesCeresAutodiff) {
  using Jet = ceres::Jet<double, 2>;
  for (const CameraModel& cam : distortedCameras()) {
    const std::array<Jet, 4> k = {Jet(cam.coeffs()[0]), Jet(cam.coeffs()[1]), Jet(cam.coeffs()[2]),
                                  Jet(cam.coeffs()[3])};
    for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.37, -0.21), Eigen::Vector2d(-1.4, 0.9),
                                     Eigen::Vector2d(1e-4, 2e-4), Eigen::Vector2d(3.0, 4.0)}) {
      Eigen::Matrix2d J;
      const Eigen::Vector2d xd = cam.distort(x, &J);
      const Jet jx(x.x(), 0), jy(x.y(), 1);
      Jet jxd, jyd;
      distortPoint(modelOf(cam), k.data(), jx, jy, jxd, jyd);
      EXPECT_NEAR(jxd.a, xd.x(), 1e-15);  // jets divide by multiplying with the inverse
      EXPECT_NEAR(jyd.a, xd.y(), 1e-15);
      Eigen::Matrix2d J_auto;
      J_auto.row(0) = jxd.v.transpose();
      J_auto.row(1) = jyd.v.transpose();
      EXPECT_LT((J_auto - J).norm(), 1e-12 * std::max(1.0, J.norm()))
          << nameOf(cam) << " at " << x.transpose();
    }
  }
}

// The Ceres templates and the class compute the same numbers (the class evaluates the template).
TEST(CameraModel, TemplatesAgreeWithTheClass) {
  for (const CameraModel& cam : distortedCameras()) {
    const std::array<double, 8> params = paramsOf(cam);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, -0.2, 1.0), Eigen::Vector3d(-2, 1.5, 0.7),
                                     Eigen::Vector3d(1e-13, 0, 1.0), Eigen::Vector3d(0, 0, 3.0),
                                     Eigen::Vector3d(5, -4, 0.2)}) {
      Eigen::Vector2d uv_class, uv_template, xd;
      ASSERT_TRUE(cam.project(p, &uv_class));
      ASSERT_TRUE(projectPoint(modelOf(cam), params.data(), p.data(), uv_template.data()));
      EXPECT_LT((uv_class - uv_template).norm(), 1e-12) << nameOf(cam) << " " << p.transpose();
      const Eigen::Vector2d xn = p.head<2>() / p.z();
      distortPoint(modelOf(cam), params.data() + 4, xn.x(), xn.y(), xd.x(), xd.y());
      EXPECT_LT((cam.distort(xn) - xd).norm(), 1e-12) << nameOf(cam) << " " << p.transpose();
    }
  }
  // The equidistant centre: the identity, as the front-end always had it.
  const CameraModel fisheye = tumviCam0();
  Eigen::Matrix2d J;
  EXPECT_EQ(fisheye.distort({1e-13, -1e-13}, &J), Eigen::Vector2d(1e-13, -1e-13));
  EXPECT_TRUE(J.isIdentity(0.0));
}

TEST(CameraModel, NoDistortionIsPlainPinhole) {
  const CameraModel cam(640, 480, 500, 510, 320, 240);
  EXPECT_EQ(cam.distortion(), CameraModel::Distortion::kNone);
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({0.2, -0.1, 2.0}, &uv));
  EXPECT_NEAR(uv.x(), 320 + 500 * 0.1, 1e-12);
  EXPECT_NEAR(uv.y(), 240 - 510 * 0.05, 1e-12);
  EXPECT_LT((cam.unproject(uv) - Eigen::Vector3d(0.1, -0.05, 1)).norm(), 1e-15);
  EXPECT_EQ(cv::countNonZero(cam.distortionCoeffs()), 0);
}

TEST(CameraModel, FromEurocCalibration) {
  CameraCalibration c;
  c.width = 752;
  c.height = 480;
  c.fx = 458.654;
  c.fy = 457.296;
  c.cx = 367.215;
  c.cy = 248.375;
  c.distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  const CameraModel cam(c);
  EXPECT_EQ(cam.distortion(), CameraModel::Distortion::kRadialTangential);
  EXPECT_EQ(cam.distort({0.1, -0.2}), eurocCam0().distort({0.1, -0.2}));
  c.distortion_model = DistortionModel::kEquidistant;
  EXPECT_EQ(CameraModel(c).distortion(), CameraModel::Distortion::kEquidistant);
  c.distortion.pop_back();
  EXPECT_THROW(CameraModel{c}, std::invalid_argument);
  EXPECT_THROW(CameraModel(0, 480, 1, 1, 0, 0), std::invalid_argument);
  EXPECT_THROW(CameraModel(640, 480, -1, 1, 0, 0), std::invalid_argument);
  EXPECT_THROW(
      CameraModel(640, 480, 1, 1, 0, 0, CameraModel::Distortion::kEquidistant, {NAN, 0, 0, 0}),
      std::invalid_argument);
}

TEST(CameraModel, DistortionModelNames) {
  DistortionModel m;
  EXPECT_TRUE(parseDistortionModel("radtan", m));
  EXPECT_EQ(m, DistortionModel::kRadialTangential);
  EXPECT_TRUE(parseDistortionModel("radial-tangential", m));
  EXPECT_TRUE(parseDistortionModel("radtan4", m));
  EXPECT_EQ(m, DistortionModel::kRadialTangential);
  EXPECT_TRUE(parseDistortionModel("equidistant", m));
  EXPECT_EQ(m, DistortionModel::kEquidistant);
  EXPECT_TRUE(parseDistortionModel("equi", m));
  EXPECT_TRUE(parseDistortionModel("fisheye", m));
  EXPECT_EQ(m, DistortionModel::kEquidistant);
  EXPECT_FALSE(parseDistortionModel("fov", m));
  EXPECT_FALSE(parseDistortionModel("Radtan", m));
  EXPECT_EQ(kalibrName(DistortionModel::kEquidistant), "equidistant");
  EXPECT_EQ(kalibrName(DistortionModel::kRadialTangential), "radtan");
}

// The simulator's camera is a description; its maths is the model's.
TEST(SimCamera, IsTheCameraModel) {
  const SimCamera euroc;  // EuRoC cam0 radtan
  EXPECT_EQ(euroc.model().distortion(), CameraModel::Distortion::kRadialTangential);
  SimCamera fisheye;
  fisheye.width = fisheye.height = 512;
  fisheye.fx = fisheye.fy = 190.97;
  fisheye.cx = 254.93;
  fisheye.cy = 256.9;
  fisheye.distortion_model = DistortionModel::kEquidistant;
  fisheye.distortion = {0.00348, 0.000715, -0.00205, 0.000203};
  EXPECT_TRUE(fisheye.hasDistortion());
  for (const SimCamera& sim : {euroc, fisheye}) {
    const CameraModel cam = sim.model();
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(0.1, -0.2, 1.0), Eigen::Vector3d(-2, 1.5, 0.7)}) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(sim.project(p, &a));
      ASSERT_TRUE(cam.project(p, &b));
      EXPECT_EQ(a, b);
      EXPECT_EQ(sim.unproject(a), cam.unproject(a));
      EXPECT_EQ(sim.distort(p.head<2>()), cam.distort(p.head<2>()));
      EXPECT_EQ(sim.undistort(p.head<2>()), cam.undistort(p.head<2>()));
    }
  }
  SimCamera pinhole;
  pinhole.distortion = {0, 0, 0, 0};
  EXPECT_FALSE(pinhole.hasDistortion());
  EXPECT_EQ(pinhole.model().distortion(), CameraModel::Distortion::kNone);
}

TEST(SimCamera, FromAndToCalibrationKeepsTheModel) {
  CameraCalibration c;
  c.width = 512;
  c.height = 512;
  c.fx = 190.97847715128717;
  c.fy = 190.9733070521226;
  c.cx = 254.93170605935475;
  c.cy = 256.8974428996504;
  c.distortion_model = DistortionModel::kEquidistant;
  c.distortion = {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
                  0.00020293673591811182};
  const SimCamera sim = simCameraFromCalibration(c, "cam0/sensor.yaml");
  EXPECT_EQ(sim.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(sim.model().distort({0.3, 0.4}), tumviCam0().distort({0.3, 0.4}));
  const CameraCalibration back = calibrationFromSimCamera(sim, Eigen::Isometry3d::Identity(), 20);
  EXPECT_EQ(back.distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(back.distortion, c.distortion);
  EXPECT_EQ(back.fx, c.fx);
  // A scaled fisheye keeps its lens: the same ray lands on the scaled pixel.
  const SimCamera half = sim.scaled(0.5);
  Eigen::Vector2d full_uv, half_uv;
  ASSERT_TRUE(sim.project({0.5, -0.3, 1.0}, &full_uv));
  ASSERT_TRUE(half.project({0.5, -0.3, 1.0}, &half_uv));
  EXPECT_LT((half_uv - ((full_uv.array() + 0.5) * 0.5 - 0.5).matrix()).norm(), 1e-9);

  c.fx = 0;
  try {
    simCameraFromCalibration(c, "cam0/sensor.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cam0/sensor.yaml"), std::string::npos) << e.what();
  }
  c.fx = 190;
  c.distortion.pop_back();
  EXPECT_THROW(simCameraFromCalibration(c, "cam0/sensor.yaml"), InputError);
}

}  // namespace
}  // namespace adugs::data

// The camera model's projections (data/camera_model.h) beyond pinhole, and every distortion on
// them: unified/MEI (Kalibr omni, camodocal MEI), double sphere (Basalt ds), extended unified
// (Basalt eucm), next to pinhole radtan/equidistant/none. Per camera: a hand-worked value,
// pixel -> ray -> pixel and ray -> pixel -> ray round trips over the whole image, the analytic
// Jacobian against central differences and against Ceres' autodiff of the template, the valid
// regions (points and pixels that have no projection are refused, never NaN), the parameter
// checks, and 'no distortion' wherever a calibration can name it.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/sim/sim_camera.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

using Jet3 = ceres::Jet<double, 3>;

struct Named {
  std::string name;
  CameraModel camera;
};

// Real calibrations of each kind (the EuRoC and TUM-VI lenses as Basalt and Kalibr fit them) and
// a few made-up ones that reach the corners of the valid regions (omni xi > 1, ds xi < 0).
std::vector<Named> cameras() {
  using D = CameraModel::Distortion;
  return {
      {"pinhole-radtan (EuRoC)",
       CameraModel(752, 480, 458.654, 457.296, 367.215, 248.375, D::kRadialTangential,
                   {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05})},
      {"pinhole-equi (TUM-VI)",
       CameraModel(512, 512, 190.978, 190.973, 254.932, 256.897, D::kEquidistant,
                   {0.00348239, 0.00071503, -0.00205324, 0.00020294})},
      {"pinhole-none", CameraModel(640, 480, 500, 510, 320, 240, D::kNone)},
      {"omni-radtan xi 0.8",
       CameraModel(752, 480, 700, 698, 376, 240, ProjectionModel::kUnified, {0.8},
                   D::kRadialTangential, {-0.2, 0.05, 0.0008, -0.0005})},
      {"omni-none xi 1.6 (image circle)",
       CameraModel(640, 640, 400, 400, 320, 320, ProjectionModel::kUnified, {1.6}, D::kNone)},
      {"ds (Basalt test camera)",
       CameraModel(1010, 1018, 402.5, 400, 505, 509, ProjectionModel::kDoubleSphere,
                   {-0.075347, 0.743925})},
      {"ds (TUM-VI)",
       CameraModel(512, 512, 158.28, 158.24, 254.93, 256.90, ProjectionModel::kDoubleSphere,
                   {-0.1748, 0.5729})},
      {"ds alpha 0.3",
       CameraModel(640, 480, 250, 250, 320, 240, ProjectionModel::kDoubleSphere, {0.4, 0.3})},
      {"eucm (EuRoC)",
       CameraModel(752, 480, 460.76484651566468, 459.4051018049483, 365.8937161309615,
                   249.33499869752445, ProjectionModel::kExtendedUnified,
                   {0.5903365915227143, 1.127468196965374})},
      {"eucm (TUM-VI)",
       CameraModel(512, 512, 191.14799816648748, 191.13150946585135, 254.95857715233118,
                   256.8815466235898, ProjectionModel::kExtendedUnified,
                   {0.6291060871161842, 1.0418067403139693})},
      {"eucm alpha 0.3",
       CameraModel(640, 480, 300, 300, 320, 240, ProjectionModel::kExtendedUnified, {0.3, 0.8})},
  };
}

// Pixel centres every `step` pixels over the whole image, borders included.
std::vector<Eigen::Vector2d> pixelGrid(const CameraModel& cam, int step) {
  std::vector<Eigen::Vector2d> px;
  for (int v = 0; v < cam.height() + step; v += step)
    for (int u = 0; u < cam.width() + step; u += step)
      px.emplace_back(std::min(u, cam.width() - 1), std::min(v, cam.height() - 1));
  return px;
}

using test::paramsOf;

std::string what(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(CameraProjections, UnifiedHandWorkedValue) {
  // Kalibr omni-radtan / camodocal MEI, xi = 0.5, k1 = 0.1, p2 = 0.01, p = (3, 0, 4):
  //   |p| = 5, den = z + xi |p| = 4 + 2.5 = 6.5, m = (3 / 6.5, 0) = (0.461538461538, 0)
  //   r2 = 0.213017751479, radial = 1 + k1 r2 = 1.021301775148
  //   xd = m radial + p2 (r2 + 2 mx^2) = 0.471370050068 + 0.006390532544 = 0.477760582613, yd = 0
  //   u = 200 xd + 320 = 415.552116522531, v = 240
  const CameraModel cam(640, 480, 200, 210, 320, 240, ProjectionModel::kUnified, {0.5},
                        CameraModel::Distortion::kRadialTangential, {0.1, 0, 0, 0.01});
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({3, 0, 4}, &uv));
  EXPECT_NEAR(uv.x(), 415.552116522531, 1e-9);
  EXPECT_NEAR(uv.y(), 240.0, 1e-12);
  Eigen::Vector3d ray;
  ASSERT_TRUE(cam.unproject(uv, &ray));
  EXPECT_LT((ray - Eigen::Vector3d(0.6, 0, 0.8)).norm(), 1e-10);
  // xi = 0: the pinhole camera with the same distortion.
  const CameraModel xi0(640, 480, 200, 210, 320, 240, ProjectionModel::kUnified, {0.0},
                        CameraModel::Distortion::kRadialTangential, {0.1, 0, 0, 0.01});
  const CameraModel pinhole(640, 480, 200, 210, 320, 240,
                            CameraModel::Distortion::kRadialTangential, {0.1, 0, 0, 0.01});
  Eigen::Vector2d a, b;
  ASSERT_TRUE(xi0.project({0.3, -0.2, 1.1}, &a));
  ASSERT_TRUE(pinhole.project({0.3, -0.2, 1.1}, &b));
  EXPECT_LT((a - b).norm(), 1e-12);
}

TEST(CameraProjections, DoubleSphereHandWorkedValue) {
  // Basalt ds, xi = 0.5, alpha = 0.6, p = (3, 0, 4):
  //   d1 = 5, k = xi d1 + z = 6.5, d2 = sqrt(3^2 + 6.5^2) = sqrt(51.25) = 7.158910531638
  //   den = alpha d2 + (1 - alpha) k = 4.295346318983 + 2.6 = 6.895346318983
  //   u = 300 * 3 / den + 256 = 386.522813266434; p = (0, -3, 4): v = 250 - 310 * 3 / den
  //   = 115.126426291351
  const CameraModel cam(512, 512, 300, 310, 256, 250, ProjectionModel::kDoubleSphere, {0.5, 0.6});
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({3, 0, 4}, &uv));
  EXPECT_NEAR(uv.x(), 386.522813266434, 1e-9);
  EXPECT_NEAR(uv.y(), 250.0, 1e-12);
  ASSERT_TRUE(cam.project({0, -3, 4}, &uv));
  EXPECT_NEAR(uv.x(), 256.0, 1e-12);
  EXPECT_NEAR(uv.y(), 115.126426291351, 1e-9);
  // alpha = 0: den = xi |p| + z, the unified model with the same xi.
  const CameraModel ds0(512, 512, 300, 310, 256, 250, ProjectionModel::kDoubleSphere, {0.5, 0.0});
  const CameraModel mei(512, 512, 300, 310, 256, 250, ProjectionModel::kUnified, {0.5});
  Eigen::Vector2d a, b;
  ASSERT_TRUE(ds0.project({0.7, -0.2, 0.3}, &a));
  ASSERT_TRUE(mei.project({0.7, -0.2, 0.3}, &b));
  EXPECT_LT((a - b).norm(), 1e-12);
}

TEST(CameraProjections, ExtendedUnifiedHandWorkedValue) {
  // Basalt eucm, alpha = 0.6, beta = 2, p = (3, 0, 4):
  //   rho = sqrt(beta (x^2 + y^2) + z^2) = sqrt(34) = 5.830951894845
  //   den = alpha rho + (1 - alpha) z = 3.498571136907 + 1.6 = 5.098571136907
  //   u = 300 * 3 / den + 256 = 432.520043720709
  const CameraModel cam(512, 512, 300, 310, 256, 250, ProjectionModel::kExtendedUnified, {0.6, 2.0});
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({3, 0, 4}, &uv));
  EXPECT_NEAR(uv.x(), 432.520043720709, 1e-9);
  EXPECT_NEAR(uv.y(), 250.0, 1e-12);
  // beta = 1: den = (1 - alpha) (z + xi |p|) with xi = alpha / (1 - alpha): the unified model
  // with focal lengths f / (1 - alpha).
  const CameraModel eucm(512, 512, 300, 310, 256, 250, ProjectionModel::kExtendedUnified, {0.6, 1.0});
  const CameraModel mei(512, 512, 300 / 0.4, 310 / 0.4, 256, 250, ProjectionModel::kUnified, {1.5});
  Eigen::Vector2d a, b;
  ASSERT_TRUE(eucm.project({0.7, -0.2, 0.3}, &a));
  ASSERT_TRUE(mei.project({0.7, -0.2, 0.3}, &b));
  EXPECT_LT((a - b).norm(), 1e-9);
}

// pixel -> ray -> pixel over the whole image, and ray -> pixel -> ray (rays compared normalised)
// for points at several depths along those rays.
TEST(CameraProjections, RoundTripsOverTheImage) {
  for (const Named& c : cameras()) {
    const CameraModel& cam = c.camera;
    int valid = 0, total = 0;
    for (const Eigen::Vector2d& uv : pixelGrid(cam, 8)) {
      ++total;
      Eigen::Vector3d ray;
      if (!cam.unproject(uv, &ray)) continue;
      ++valid;
      EXPECT_NEAR(ray.norm(), 1.0, 1e-12) << c.name;
      Eigen::Vector2d back;
      ASSERT_TRUE(cam.project(ray, &back)) << c.name << " pixel " << uv.transpose();
      EXPECT_LT((back - uv).norm(), 1e-7) << c.name << " pixel " << uv.transpose();
      for (double depth : {0.3, 2.0, 40.0}) {
        Eigen::Vector2d px;
        ASSERT_TRUE(cam.project(depth * ray, &px)) << c.name;
        Eigen::Vector3d again;
        ASSERT_TRUE(cam.unproject(px, &again)) << c.name << " pixel " << px.transpose();
        EXPECT_LT((again - ray).norm(), 1e-9) << c.name << " pixel " << uv.transpose();
      }
      // The (x, y, 1) interface, for rays in front of the camera.
      if (ray.z() > 0.05) {
        const Eigen::Vector2d xn = cam.pixelToNormalized(uv);
        EXPECT_LT((xn - ray.head<2>() / ray.z()).norm(), 1e-9 * (1 + xn.norm())) << c.name;
        EXPECT_LT((cam.normalizedToPixel(xn) - uv).norm(), 1e-7) << c.name;
      }
    }
    // Every real lens sees most of its image; the made-up image circles at least half of it.
    EXPECT_GT(valid, total / 2) << c.name;
  }
}

TEST(CameraProjections, AnalyticJacobianMatchesCentralDifferences) {
  for (const Named& c : cameras()) {
    const CameraModel& cam = c.camera;
    int checked = 0;
    for (const Eigen::Vector2d& uv : pixelGrid(cam, 37)) {
      Eigen::Vector3d ray;
      if (!cam.unproject(uv, &ray)) continue;
      const Eigen::Vector3d p = 1.7 * ray;
      Eigen::Vector2d px;
      Eigen::Matrix<double, 2, 3> J;
      ASSERT_TRUE(cam.project(p, &px, &J));
      Eigen::Matrix<double, 2, 3> Jn;
      const double h = 1e-6 * p.norm();
      bool ok = true;
      for (int i = 0; i < 3; ++i) {
        Eigen::Vector3d dp = Eigen::Vector3d::Zero();
        dp[i] = h;
        Eigen::Vector2d a, b;
        ok = ok && cam.project(p + dp, &a) && cam.project(p - dp, &b);
        Jn.col(i) = (a - b) / (2 * h);
      }
      if (!ok) continue;  // at the edge of the valid region
      ++checked;
      EXPECT_LT((J - Jn).norm(), 1e-6 * J.norm() + 1e-6) << c.name << " pixel " << uv.transpose()
                                                         << "\n" << J << "\n" << Jn;
      // Ceres' autodiff of the template agrees with the class to rounding.
      const std::array<double, 8> params = paramsOf(cam);
      const std::vector<double> q = cam.projectionParams();
      Jet3 pj[3], qj[2], kj[8], uvj[2];
      for (int i = 0; i < 3; ++i) pj[i] = Jet3(p[i], i);
      for (size_t i = 0; i < q.size(); ++i) qj[i] = Jet3(q[i]);
      for (int i = 0; i < 8; ++i) kj[i] = Jet3(params[static_cast<size_t>(i)]);
      ASSERT_TRUE(projectPoint(cam.projection(), qj, CameraModel::toModel(cam.distortion()), kj,
                               pj, uvj));
      EXPECT_NEAR(uvj[0].a, px.x(), 1e-9) << c.name;
      EXPECT_NEAR(uvj[1].a, px.y(), 1e-9) << c.name;
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(uvj[0].v[i], J(0, i), 1e-9 * (1 + J.norm())) << c.name;
        EXPECT_NEAR(uvj[1].v[i], J(1, i), 1e-9 * (1 + J.norm())) << c.name;
      }
    }
    EXPECT_GT(checked, 20) << c.name;
  }
}

// distort() is the whole lens from the pinhole normalised plane: its Jacobian too.
TEST(CameraProjections, NormalisedPlaneJacobian) {
  for (const Named& c : cameras()) {
    for (const Eigen::Vector2d& xn : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-1.1, 0.6)}) {
      Eigen::Matrix2d J, Jn;
      c.camera.distort(xn, &J);
      for (int i = 0; i < 2; ++i) {
        Eigen::Vector2d d = Eigen::Vector2d::Zero();
        d[i] = 1e-6;
        Jn.col(i) = (c.camera.distort(xn + d) - c.camera.distort(xn - d)) / 2e-6;
      }
      EXPECT_LT((J - Jn).norm(), 1e-6 * J.norm()) << c.name;
    }
  }
}

TEST(CameraProjections, PointsOutsideTheValidRegionDoNotProject) {
  const Eigen::Vector2d untouched(-7, -7);
  auto refuses = [&](const CameraModel& cam, const Eigen::Vector3d& p) {
    Eigen::Vector2d uv = untouched;
    Eigen::Matrix<double, 2, 3> J;
    const bool ok = cam.project(p, &uv, &J);
    return !ok && uv == untouched;
  };
  auto accepts = [&](const CameraModel& cam, const Eigen::Vector3d& p) {
    Eigen::Vector2d uv;
    return cam.project(p, &uv) && uv.allFinite();
  };
  // A direction at angle theta off the optical axis.
  auto at = [](double theta) { return Eigen::Vector3d(std::sin(theta), 0.0, std::cos(theta)); };
  const double eps = 1e-6;
  // omni xi = 0.8: z > -0.8 |p| (Kalibr): beyond 90 degrees, up to acos(-0.8) = 143.1 degrees.
  const CameraModel omni(640, 480, 300, 300, 320, 240, ProjectionModel::kUnified, {0.8});
  EXPECT_TRUE(accepts(omni, at(std::acos(-0.8) - eps)));
  EXPECT_TRUE(refuses(omni, at(std::acos(-0.8) + eps)));
  EXPECT_TRUE(refuses(omni, {0, 0, -1}));
  // omni xi = 1.6: z > -|p| / 1.6.
  const CameraModel omni16(640, 480, 300, 300, 320, 240, ProjectionModel::kUnified, {1.6});
  EXPECT_TRUE(accepts(omni16, at(std::acos(-1 / 1.6) - eps)));
  EXPECT_TRUE(refuses(omni16, at(std::acos(-1 / 1.6) + eps)));
  // ds xi = 0.4, alpha = 0.3: w1 = 3/7, w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1).
  const CameraModel ds(640, 480, 250, 250, 320, 240, ProjectionModel::kDoubleSphere, {0.4, 0.3});
  const double w1 = 0.3 / 0.7, w2 = (w1 + 0.4) / std::sqrt(2 * w1 * 0.4 + 0.16 + 1);
  EXPECT_TRUE(accepts(ds, at(std::acos(-w2) - eps)));
  EXPECT_TRUE(refuses(ds, at(std::acos(-w2) + eps)));
  // eucm alpha = 0.6, beta = 2: z > -w rho, w = (1 - alpha) / alpha = 2/3; on the x-z plane
  // z = -w sqrt(beta x^2 + z^2) at tan(theta) = -sqrt((1 - w^2) / (beta w^2)).
  const CameraModel eucm(640, 480, 250, 250, 320, 240, ProjectionModel::kExtendedUnified, {0.6, 2.0});
  const double w = 2.0 / 3.0;
  const double edge = M_PI - std::atan(std::sqrt((1 - w * w) / (2 * w * w)));
  EXPECT_TRUE(accepts(eucm, at(edge - eps)));
  EXPECT_TRUE(refuses(eucm, at(edge + eps)));
  // The origin projects nowhere.
  for (const Named& c : cameras()) EXPECT_TRUE(refuses(c.camera, {0, 0, 0})) << c.name;
}

// Pixels outside the image a lens can form (omni xi > 1, ds/eucm alpha > 0.5) are reported,
// and the (x, y, 1) interface clamps them, and rays behind the camera, to just short of 90
// degrees in their direction: finite, never NaN.
TEST(CameraProjections, PixelsWithoutARayAreReported) {
  for (const Named& c : cameras()) {
    const CameraModel& cam = c.camera;
    for (const Eigen::Vector2d& uv : pixelGrid(cam, 16)) {
      Eigen::Vector3d ray(7, 7, 7);
      const bool ok = cam.unproject(uv, &ray);
      if (!ok) {
        EXPECT_EQ(ray, Eigen::Vector3d(7, 7, 7)) << c.name;  // a failed unprojection leaves it
      }
      const Eigen::Vector2d xn = cam.pixelToNormalized(uv);
      ASSERT_TRUE(xn.allFinite()) << c.name << " pixel " << uv.transpose();
      if (!ok || ray.z() <= 0) {
        EXPECT_GT(xn.norm(), 1e8) << c.name << " pixel " << uv.transpose();
        // In the pixel's direction from the principal point.
        const Eigen::Vector2d dir((uv.x() - cam.cx()) / cam.fx(), (uv.y() - cam.cy()) / cam.fy());
        EXPECT_GT(xn.normalized().dot(dir.normalized()), 0.99) << c.name;
      }
    }
  }
  // The Basalt ds test camera (alpha 0.74): its image circle r^2 < 1 / (2 alpha - 1) misses the
  // corners; the omni xi = 0.8 camera sees past 90 degrees at its corners.
  const CameraModel ds(1010, 1018, 402.5, 400, 505, 509, ProjectionModel::kDoubleSphere,
                       {-0.075347, 0.743925});
  Eigen::Vector3d ray;
  EXPECT_FALSE(ds.unproject({0, 0}, &ray));
  EXPECT_TRUE(ds.unproject({505, 509}, &ray));
  const CameraModel omni(640, 480, 120, 120, 320, 240, ProjectionModel::kUnified, {0.8});
  ASSERT_TRUE(omni.unproject({0, 0}, &ray));
  EXPECT_LT(ray.z(), 0);
  const Eigen::Vector2d xn = omni.pixelToNormalized({0, 0});
  EXPECT_TRUE(xn.allFinite());
  EXPECT_GT(xn.norm(), 1e8);
  EXPECT_LT(xn.x(), 0);
  EXPECT_LT(xn.y(), 0);
}

TEST(CameraProjections, InvalidParametersThrowNamingTheParameter) {
  using D = CameraModel::Distortion;
  auto make = [](ProjectionModel m, std::vector<double> q, D d = D::kNone,
                 std::array<double, 4> k = {}) {
    return [=] { CameraModel(640, 480, 300, 300, 320, 240, m, q, d, k); };
  };
  EXPECT_NE(what(make(ProjectionModel::kUnified, {-0.1})).find("xi"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kUnified, {NAN})).find("xi"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kDoubleSphere, {0.2, 1.2})).find("alpha"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kDoubleSphere, {0.2, -0.1})).find("alpha"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kDoubleSphere, {-1.5, 0.5})).find("xi"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kExtendedUnified, {1.01, 1})).find("alpha"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kExtendedUnified, {0.5, 0})).find("beta"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kExtendedUnified, {0.5})).find("projection_params"),
            std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kPinhole, {0.5})).find("projection_params"), std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kDoubleSphere, {0.2, 0.5}, D::kRadialTangential, {0.1, 0, 0, 0}))
                .find("distortion_model"),
            std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kExtendedUnified, {0.5, 1}, D::kEquidistant))
                .find("distortion_model"),
            std::string::npos);
  EXPECT_NE(what(make(ProjectionModel::kUnified, {0.5}, D::kEquidistant)).find("equidistant"),
            std::string::npos);
  // The calibration's default distortion (radtan, zero coefficients) is no distortion.
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 300;
  c.cx = 320;
  c.cy = 240;
  c.projection = ProjectionModel::kDoubleSphere;
  c.projection_params = {0.1, 0.6};
  c.distortion = {0, 0, 0, 0};
  EXPECT_EQ(CameraModel(c).distortion(), D::kNone);
  EXPECT_EQ(CameraModel(c).projectionParams(), c.projection_params);
  c.projection_params = {0.1};
  EXPECT_NE(what([&] { CameraModel{c}; }).find("projection_params"), std::string::npos);
}

TEST(CameraProjections, NoDistortionIsNoDistortionEverywhere) {
  // The template, the class, a calibration, the simulator's camera and the names.
  double xd = 0, yd = 0;
  const double d[4] = {0.3, 0.2, 0.1, 0.05};  // ignored
  distortPoint(DistortionModel::kNone, d, 0.4, -0.3, xd, yd);
  EXPECT_EQ(xd, 0.4);
  EXPECT_EQ(yd, -0.3);
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.fx = 500;
  c.fy = 510;
  c.cx = 320;
  c.cy = 240;
  c.distortion_model = DistortionModel::kNone;
  c.distortion = {0, 0, 0, 0};
  const CameraModel cam(c);
  EXPECT_EQ(cam.distortion(), CameraModel::Distortion::kNone);
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam.project({0.2, -0.1, 2.0}, &uv));
  EXPECT_NEAR(uv.x(), 320 + 500 * 0.1, 1e-12);
  EXPECT_NEAR(uv.y(), 240 - 510 * 0.05, 1e-12);
  EXPECT_EQ(cam.pixelToNormalized(uv), Eigen::Vector2d(0.1, -0.05));
  c.distortion.clear();  // 'none' may come without its zeros
  EXPECT_EQ(CameraModel(c).distortion(), CameraModel::Distortion::kNone);
  c.distortion = {0, 0, 0, 0};

  SimCamera sim = simCameraFromCalibration(c, "sensor.yaml");
  EXPECT_FALSE(sim.hasDistortion());
  EXPECT_EQ(sim.model().distortion(), CameraModel::Distortion::kNone);
  EXPECT_EQ(calibrationFromSimCamera(sim, Eigen::Isometry3d::Identity(), 20).distortion_model,
            DistortionModel::kNone);

  DistortionModel m = DistortionModel::kRadialTangential;
  EXPECT_TRUE(parseDistortionModel("none", m));
  EXPECT_EQ(m, DistortionModel::kNone);
  EXPECT_EQ(kalibrName(DistortionModel::kNone), "none");
  EXPECT_EQ(CameraModel::fromModel(DistortionModel::kNone), CameraModel::Distortion::kNone);

  // EuRoC sensor.yaml: 'none' is written and read back.
  c.rate_hz = 20;
  const CameraCalibration back = parseEurocCameraYaml(formatEurocCameraYaml(c), "sensor.yaml");
  EXPECT_EQ(back.distortion_model, DistortionModel::kNone);
  EXPECT_EQ(back.projection, ProjectionModel::kPinhole);
}

// The focal length on the axis: the pinhole's, and fx / (1 + xi) for omni and ds (den = 1 + xi
// there), fx for eucm (den = 1).
TEST(CameraProjections, CentreFocalLength) {
  EXPECT_NEAR(CameraModel(640, 480, 500, 510, 320, 240).centreFocalPx(), 505, 1e-9);
  EXPECT_NEAR(CameraModel(640, 480, 500, 510, 320, 240, CameraModel::Distortion::kRadialTangential,
                          {-0.3, 0.1, 0.001, 0.002})
                  .centreFocalPx(),
              505, 1e-9);
  EXPECT_NEAR(CameraModel(640, 480, 600, 600, 320, 240, ProjectionModel::kUnified, {0.5})
                  .centreFocalPx(),
              400, 1e-9);
  EXPECT_NEAR(CameraModel(640, 480, 349.7, 348.7, 320, 240, ProjectionModel::kDoubleSphere,
                          {-0.2441, 0.5662})
                  .centreFocalPx(),
              349.2 / 0.7559, 1e-9);
  EXPECT_NEAR(CameraModel(640, 480, 460, 458, 320, 240, ProjectionModel::kExtendedUnified,
                          {0.59, 1.13})
                  .centreFocalPx(),
              459, 1e-9);
}

TEST(CameraProjections, ProjectionNames) {
  ProjectionModel m = ProjectionModel::kPinhole;
  EXPECT_TRUE(parseProjectionModel("omni", m));
  EXPECT_EQ(m, ProjectionModel::kUnified);
  EXPECT_TRUE(parseProjectionModel("MEI", m));
  EXPECT_EQ(m, ProjectionModel::kUnified);
  EXPECT_TRUE(parseProjectionModel("ds", m));
  EXPECT_EQ(m, ProjectionModel::kDoubleSphere);
  EXPECT_TRUE(parseProjectionModel("eucm", m));
  EXPECT_EQ(m, ProjectionModel::kExtendedUnified);
  EXPECT_TRUE(parseProjectionModel("pinhole", m));
  EXPECT_EQ(m, ProjectionModel::kPinhole);
  EXPECT_FALSE(parseProjectionModel("fov", m));
  for (ProjectionModel p : {ProjectionModel::kPinhole, ProjectionModel::kUnified,
                            ProjectionModel::kDoubleSphere, ProjectionModel::kExtendedUnified}) {
    ProjectionModel back;
    ASSERT_TRUE(parseProjectionModel(toString(p), back));
    EXPECT_EQ(back, p);
  }
}

// The EuRoC sensor.yaml carries the projection in two optional keys, written only when it is
// not pinhole.
TEST(CameraProjections, EurocSensorYamlCarriesTheProjection) {
  CameraCalibration c;
  c.width = 752;
  c.height = 480;
  c.fx = 349.7;
  c.fy = 348.7;
  c.cx = 365.8;
  c.cy = 249.0;
  c.projection = ProjectionModel::kDoubleSphere;
  c.projection_params = {-0.2441, 0.5662};
  c.distortion_model = DistortionModel::kNone;
  c.distortion = {0, 0, 0, 0};
  c.rate_hz = 20;
  const std::string text = formatEurocCameraYaml(c);
  // The model is named by camera_model, so a pinhole-only EuRoC reader refuses the file rather
  // than taking the lens for a pinhole.
  EXPECT_NE(text.find("camera_model: ds\nintrinsics: [349.7, 348.7, 365.8, 249] #fu, fv, cu, cv\n"
                      "projection_params: [-0.2441, 0.5662]\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("camera_model: pinhole"), std::string::npos) << text;
  const CameraCalibration back = parseEurocCameraYaml(text, "sensor.yaml");
  EXPECT_EQ(back.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(back.projection_params, c.projection_params);
  EXPECT_EQ(back.distortion_model, DistortionModel::kNone);

  c.projection = ProjectionModel::kPinhole;
  c.projection_params.clear();
  EXPECT_EQ(formatEurocCameraYaml(c).find("projection"), std::string::npos);

  // A wrong count or name is an error naming the key.
  std::string bad = text;
  bad.replace(bad.find("[-0.2441, 0.5662]"), 17, "[-0.2441]");
  try {
    parseEurocCameraYaml(bad, "sensor.yaml");
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("projection_params"), std::string::npos) << e.what();
  }
  bad = text;
  bad.replace(bad.find("camera_model: ds"), 16, "camera_model: fov");
  EXPECT_ANY_THROW(parseEurocCameraYaml(bad, "sensor.yaml"));

  // The form adugs wrote before (camera_model: pinhole + projection:) still reads; a projection
  // that disagrees with camera_model is an error naming the key.
  std::string legacy = text;
  legacy.replace(legacy.find("camera_model: ds"), 16, "camera_model: pinhole\nprojection: ds");
  const CameraCalibration old = parseEurocCameraYaml(legacy, "sensor.yaml");
  EXPECT_EQ(old.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(old.projection_params, (std::vector<double>{-0.2441, 0.5662}));
  bad = text;
  bad.replace(bad.find("camera_model: ds"), 16, "camera_model: eucm\nprojection: ds");
  try {
    parseEurocCameraYaml(bad, "sensor.yaml");
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("disagrees with camera_model 'eucm'"), std::string::npos) << e.what();
  }
}

TEST(CameraProjections, SimCameraCarriesTheProjection) {
  SimCamera sim;
  sim.projection = ProjectionModel::kExtendedUnified;
  sim.projection_params = {0.5903365915227143, 1.127468196965374};
  sim.distortion_model = DistortionModel::kNone;
  sim.distortion = {0, 0, 0, 0};
  EXPECT_TRUE(sim.hasDistortion());  // bends lines
  EXPECT_EQ(sim.model().projection(), ProjectionModel::kExtendedUnified);
  const CameraCalibration c = calibrationFromSimCamera(sim, Eigen::Isometry3d::Identity(), 20);
  EXPECT_EQ(c.projection, ProjectionModel::kExtendedUnified);
  EXPECT_EQ(c.projection_params, sim.projection_params);
  const SimCamera back = simCameraFromCalibration(c, "sensor.yaml");
  EXPECT_EQ(back.projection_params, sim.projection_params);
  // Scaling keeps the lens: the same ray lands on the scaled pixel.
  const SimCamera half = sim.scaled(0.5);
  Eigen::Vector2d full_uv, half_uv;
  ASSERT_TRUE(sim.project({0.9, -0.3, 0.4}, &full_uv));
  ASSERT_TRUE(half.project({0.9, -0.3, 0.4}, &half_uv));
  EXPECT_LT((half_uv - ((full_uv.array() + 0.5) * 0.5 - 0.5).matrix()).norm(), 1e-9);
}

}  // namespace
}  // namespace adugs::data

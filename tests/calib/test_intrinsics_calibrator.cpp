#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/intrinsics/intrinsics_report.h"
#include "calib/intrinsics/intrinsics_verdict.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "calib/target/corner_csv.h"
#include "data/camera_model.h"
#include "data/input_error.h"
#include "tests/calib/camera_imu_synthetic.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

void expectWithin(const CalibCamera& got, const CalibCamera& truth, double rel) {
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(got.params[i], truth.params[i], rel * std::abs(truth.params[i]))
        << "param " << i;
}

// The calibration's parameter block is the product's camera model (tests/data/test_camera_model
// checks the maths): same pixels, and unproject says when a fisheye pixel has no z = 1 ray.
TEST(CalibCamera, IsTheDataCameraModel) {
  for (const CalibCamera& cam : {synth::eurocLikeCamera(), synth::fisheyeCamera()}) {
    const data::CameraModel model(cam.toEuroc());
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(0.1, -0.2, 1.0), Eigen::Vector3d(-0.6, 0.5, 0.9)}) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(cam.project(p, a));
      ASSERT_TRUE(model.project(p, &b));
      EXPECT_EQ(a, b);
      Eigen::Vector3d ray;
      ASSERT_TRUE(cam.unproject(a, ray));
      EXPECT_EQ(ray, model.unproject(a));
    }
    Eigen::Vector2d uv;
    EXPECT_FALSE(cam.project({0, 0, -1}, uv));
  }
  // The fisheye's image corner is more than 90 degrees off-axis.
  Eigen::Vector3d ray;
  EXPECT_FALSE(synth::fisheyeCamera().unproject({0, 0}, ray));
}

TEST(IntrinsicsCalibrator, RecoversRadtanFromNoisySyntheticViews) {
  const CalibCamera truth = synth::eurocLikeCamera();
  const auto views = synth::syntheticViews(truth, AprilGrid{}, 25, 0.2);
  IntrinsicsOptions o;
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, o);
  expectWithin(r.camera, truth, 0.001);  // 0.1 %
  EXPECT_NEAR(r.camera.params[4], truth.params[4], 0.005);
  EXPECT_NEAR(r.camera.params[5], truth.params[5], 0.01);
  EXPECT_NEAR(r.rms_px, 0.2 * std::sqrt(2.0), 0.05);  // the noise we added
  EXPECT_EQ(r.views.size(), 25u);
  ASSERT_TRUE(r.has_sigma);
  EXPECT_LT(r.sigma[0], 0.5);
  EXPECT_EQ(judgeIntrinsics(r, o).verdict.verdict, Verdict::kOk);
}

TEST(IntrinsicsCalibrator, RecoversEquidistantFromNoisySyntheticViews) {
  const CalibCamera truth = synth::fisheyeCamera();
  const auto views = synth::syntheticViews(truth, AprilGrid{}, 25, 0.2, 11, 0.35, 0.7);
  IntrinsicsOptions o;
  o.model = DistortionModel::kEquidistant;
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, o);
  expectWithin(r.camera, truth, 0.001);
  // k1..k4 trade off against each other over the angles the views cover; what matters is the
  // projection: compare it over the part of the image the views cover.
  double covered = 0;
  for (const auto& v : views)
    for (const auto& c : v.corners)
      covered = std::max(covered, std::hypot(c.pixel.x() - truth.pu(), c.pixel.y() - truth.pv()));
  EXPECT_GT(covered, 300);
  covered *= 0.9;  // the rim has few corners
  double worst = 0;
  for (double u = truth.pu() - covered; u <= truth.pu() + covered; u += 10)
    for (double v = truth.pv() - covered; v <= truth.pv() + covered; v += 10) {
      Eigen::Vector3d ray;
      if (std::hypot(u - truth.pu(), v - truth.pv()) > covered || !truth.unproject({u, v}, ray))
        continue;
      Eigen::Vector2d uv;
      ASSERT_TRUE(r.camera.project(ray, uv));
      worst = std::max(worst, (uv - Eigen::Vector2d(u, v)).norm());
    }
  EXPECT_LT(worst, 0.2);
  EXPECT_EQ(judgeIntrinsics(r, o).verdict.verdict, Verdict::kOk);
}

// Issue 18's weak case, rebuilt: a camera held still in front of the board (face-on, 30 views,
// a few mm of jitter; the old start was 6000-9800 px and the old result fu 8800-46000 px,
// k2 up to 8e6, exit 0). Now the focal length stays in the plausible range, and the verdict is
// failed: its 1-sigma is many times the focal length itself (more than 10 %: not determined).
TEST(IntrinsicsCalibrator, NearStillViewsAreNeverOk) {
  CalibCamera cam1 = synth::eurocLikeCamera();  // EuRoC cam1
  cam1.params = {457.587, 456.134, 379.999, 255.238, -0.28368365, 0.07451284, -0.00010473, -3.555e-05};
  const auto views = synth::nearStillViews(cam1, synth::eurocGrid(), 30, 0.2, 1, 1.1, 0, 0.002, 0.1);
  const IntrinsicsOptions o;
  const IntrinsicsResult r = calibrateIntrinsics(views, 752, 480, o);
  EXPECT_GE(r.initial_focal_px, 0.2 * 752);
  EXPECT_LE(r.initial_focal_px, 5 * 752);
  EXPECT_GE(r.camera.fu(), 0.2 * 752 * 0.999);
  EXPECT_LE(r.camera.fu(), 5 * 752 * 1.001);
  const IntrinsicsJudgement j = judgeIntrinsics(r, o);
  EXPECT_EQ(j.verdict.verdict, Verdict::kFailed) << formatVerdict(j.verdict, "");
  EXPECT_TRUE(j.verdict.has("undetermined"));
  EXPECT_TRUE(j.poorly_determined[0] && j.poorly_determined[1]);
  EXPECT_GT(r.sigma[0], r.camera.fu());  // the covariance knows
  EXPECT_TRUE(j.verdict.has("tilt"));
  EXPECT_TRUE(j.verdict.has("coverage"));
}

// One pose held for 30 views (board tilted 20 deg): weak, the focal lengths named (documented
// verdict of a single-pose set; the focal length comes out 1-7 % off over five seeds).
TEST(IntrinsicsCalibrator, SinglePoseSetIsWeak) {
  const CalibCamera cam = synth::eurocLikeCamera();
  const auto views = synth::nearStillViews(cam, synth::eurocGrid(), 30, 0.3, 3, 1.0, 20, 0, 0);
  const IntrinsicsOptions o;
  const IntrinsicsJudgement j = judgeIntrinsics(calibrateIntrinsics(views, 752, 480, o), o);
  EXPECT_EQ(j.verdict.verdict, Verdict::kWeak) << formatVerdict(j.verdict, "");
  EXPECT_TRUE(j.poorly_determined[0] && j.poorly_determined[1]);
  EXPECT_LT(j.coverage.tilt_spread_deg, 1.0);
  // Tilted 20 deg, one pose still gives the focal length to a few percent (weak, not failed).
  EXPECT_LT(j.verdict.findings.size(), 10u);
  EXPECT_FALSE(j.verdict.has("undetermined"));
}

// Exact corners: recovered exactly, nothing rejected (sigma has a floor), verdict ok.
TEST(IntrinsicsCalibrator, NoiseFreeViewsAreRecoveredExactly) {
  const CalibCamera truth = synth::eurocLikeCamera();
  const auto views = synth::syntheticViews(truth, AprilGrid{}, 12, 0.0, 9);
  const IntrinsicsOptions o;
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, o);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(r.camera.params[i], truth.params[i], 1e-6 * std::max(1.0, std::abs(truth.params[i]))) << i;
  EXPECT_EQ(r.outliers, 0);
  EXPECT_EQ(judgeIntrinsics(r, o).verdict.verdict, Verdict::kOk);
}

TEST(IntrinsicsCalibrator, RejectsGrossOutliers) {
  const CalibCamera truth = synth::eurocLikeCamera();
  auto views = synth::syntheticViews(truth, AprilGrid{}, 15, 0.2, 3);
  int spoiled = 0;
  for (auto& v : views)
    for (size_t i = 0; i < v.corners.size(); i += 37, ++spoiled) v.corners[i].pixel += Eigen::Vector2d(6, -4);
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, {});
  EXPECT_GE(r.outliers, spoiled);
  expectWithin(r.camera, truth, 0.002);
  int flagged = 0;
  for (const auto& c : r.residuals) flagged += !c.inlier && c.residual.norm() > 5;
  EXPECT_EQ(flagged, spoiled);
}

TEST(IntrinsicsCalibrator, TooFewViewsIsAnInputError) {
  const CalibCamera truth = synth::eurocLikeCamera();
  auto views = synth::syntheticViews(truth, AprilGrid{}, 2, 0.2);
  IntrinsicsOptions o;
  o.min_views = 3;
  try {
    calibrateIntrinsics(views, truth.width, truth.height, o);
    FAIL() << "expected InputError";
  } catch (const data::InputError& e) {
    EXPECT_EQ(e.field(), "views");
    EXPECT_NE(std::string(e.what()).find("too few views"), std::string::npos) << e.what();
  }
  // Views with too few corners do not count.
  for (auto& v : views) v.corners.resize(5);
  EXPECT_THROW(calibrateIntrinsics(views, truth.width, truth.height, IntrinsicsOptions{}),
               data::InputError);
  EXPECT_THROW(calibrateIntrinsics({}, truth.width, truth.height, IntrinsicsOptions{}),
               data::InputError);
}

// The real EuRoC cam_april detections (30 consecutive frames at 1.1-1.2 m).
class EurocCamApril : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::sharedDataDir() / "euroc_calib_aprilgrid" / "cam_april" / "cam0";
    ADUGS_REQUIRE_SHARED(dir_);
    views_ = readCornerCsvs(dir_.string(), nullptr);
  }
  std::filesystem::path dir_;
  std::vector<TargetObservation> views_;
};

// Without outlier rejection our solution is the plain least-squares one, which OpenCV's
// independent calibrateCamera (same radtan model, k3 fixed at 0) must reproduce.
TEST_F(EurocCamApril, PlainLeastSquaresAgreesWithOpenCv) {
  IntrinsicsOptions o;
  o.outlier_sigma = 0;
  o.compute_covariance = false;
  const IntrinsicsResult r = calibrateIntrinsics(views_, 752, 480, o);
  std::vector<std::vector<cv::Point3f>> obj;
  std::vector<std::vector<cv::Point2f>> img;
  for (const auto& v : views_) {
    obj.emplace_back();
    img.emplace_back();
    for (const auto& c : v.corners) {
      obj.back().emplace_back(float(c.point.x()), float(c.point.y()), 0.f);
      img.back().emplace_back(float(c.pixel.x()), float(c.pixel.y()));
    }
  }
  cv::Mat K = (cv::Mat_<double>(3, 3) << 460, 0, 376, 0, 460, 240, 0, 0, 1), D;
  std::vector<cv::Mat> rv, tv;
  const double rms = cv::calibrateCamera(obj, img, cv::Size(752, 480), K, D, rv, tv,
                                         cv::CALIB_USE_INTRINSIC_GUESS | cv::CALIB_FIX_K3);
  EXPECT_NEAR(r.rms_px, rms, 1e-3);
  EXPECT_NEAR(r.camera.fu(), K.at<double>(0, 0), 0.05);
  EXPECT_NEAR(r.camera.fv(), K.at<double>(1, 1), 0.05);
  EXPECT_NEAR(r.camera.pu(), K.at<double>(0, 2), 0.05);
  EXPECT_NEAR(r.camera.pv(), K.at<double>(1, 2), 0.05);
  EXPECT_NEAR(r.camera.params[4], D.at<double>(0), 1e-3);
}

// Issue 18's bar for these 30 near-identical views (consecutive frames over 1.5 s, the board in
// the upper-left 40 % of the image, its normal within 20 deg): verdict weak, focal within 10 % of
// EuRoC's published cam0 values, and the report names the poorly determined parameters. We get
// +2.0 % (fu, fv), +1.2 % / +0.9 % (pu, pv), RMS 0.15 px.
TEST_F(EurocCamApril, WeakWithTheFocalWithinTenPercent) {
  const IntrinsicsOptions o;
  const IntrinsicsResult r = calibrateIntrinsics(views_, 752, 480, o);
  const IntrinsicsJudgement j = judgeIntrinsics(r, o);
  const double published[4] = {458.654, 457.296, 367.215, 248.375};
  EXPECT_EQ(j.verdict.verdict, Verdict::kWeak) << formatVerdict(j.verdict, "");
  EXPECT_NEAR(r.camera.fu(), published[0], 0.10 * published[0]);
  EXPECT_NEAR(r.camera.fv(), published[1], 0.10 * published[1]);
  EXPECT_LT(r.rms_px, 0.3);
  EXPECT_EQ(r.views.size(), 30u);
  EXPECT_TRUE(j.verdict.has("coverage"));
  EXPECT_LT(j.coverage.image_share, 0.5);
  // Named: the focal lengths (one viewing angle) and what the uncovered image leaves open.
  for (int i : {0, 1, 2, 3, 4, 5}) EXPECT_TRUE(j.poorly_determined[static_cast<size_t>(i)]) << i;
  ReportContext ctx;
  ctx.input = dir_.string();
  const std::string report = formatIntrinsicsReport(r, j, ctx);
  EXPECT_NE(report.find("WARNING: verdict WEAK"), std::string::npos);
  EXPECT_NE(report.find("fu (the board was seen at one angle)"), std::string::npos) << report;
  EXPECT_NE(report.find("<- poorly determined"), std::string::npos);
}

// Issue 18's bar on varied real views: EuRoC imu_april cam0 detections, every 20th frame (70
// views, the board all over the image): fu, fv within 1 %, pu, pv within 2 % of the published
// cam0 intrinsics, verdict ok. We get +0.44 / +0.64 % and -1.78 / -1.20 % (every 10th frame:
// +0.24 / +0.45 % and -1.84 / -1.32 %).
TEST(EurocImuApril, VariedViewsMeetThePublishedIntrinsics) {
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "imu_april" / "cam0";
  ADUGS_REQUIRE_SHARED(dir);
  const auto all = readCornerCsvs(dir.string(), nullptr);
  std::vector<TargetObservation> views;
  for (size_t i = 0; i < all.size(); i += 20) views.push_back(all[i]);
  const IntrinsicsOptions o;
  const IntrinsicsResult r = calibrateIntrinsics(views, 752, 480, o);
  const IntrinsicsJudgement j = judgeIntrinsics(r, o);
  const double published[4] = {458.654, 457.296, 367.215, 248.375};
  EXPECT_NEAR(r.camera.fu(), published[0], 0.01 * published[0]);
  EXPECT_NEAR(r.camera.fv(), published[1], 0.01 * published[1]);
  EXPECT_NEAR(r.camera.pu(), published[2], 0.02 * published[2]);
  EXPECT_NEAR(r.camera.pv(), published[3], 0.02 * published[3]);
  EXPECT_EQ(j.verdict.verdict, Verdict::kOk) << formatVerdict(j.verdict, "");
  EXPECT_GT(j.coverage.image_share, 0.9);
}

}  // namespace
}  // namespace adugs::calib

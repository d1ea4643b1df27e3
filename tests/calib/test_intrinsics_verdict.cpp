// The intrinsics verdict: coverage and tilt measured on hand-made cases, the lens-model fold, each
// plausibility check turning a result into `failed`, and how a verdict is written.
#include "calib/intrinsics/intrinsics_verdict.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "tests/calib/synthetic_views.h"

namespace adugs::calib {
namespace {

// r_d = r (1 + k1 r^2) with k1 = -0.5 stops growing where 1 - 1.5 r^2 = 0: r = sqrt(2/3),
// r_d = sqrt(2/3) (1 - 1/3) = 0.5443.
TEST(IntrinsicsVerdict, DistortionFoldRadiusHandWorked) {
  CalibCamera c = synth::eurocLikeCamera();
  c.params = {400, 400, 320, 240, -0.5, 0, 0, 0};
  EXPECT_NEAR(distortionFoldRadius(c), std::sqrt(2.0 / 3) * (2.0 / 3), 2e-3);
  c.params[4] = -0.2834;  // EuRoC: 1 - 0.85 r^2 + 0.37 r^4 > 0 everywhere
  c.params[5] = 0.0740;
  EXPECT_TRUE(std::isinf(distortionFoldRadius(c)));
  c.model = DistortionModel::kEquidistant;  // theta_d = theta: never folds
  c.params = {300, 300, 320, 240, 0, 0, 0, 0};
  EXPECT_TRUE(std::isinf(distortionFoldRadius(c)));
}

// Two views: one face-on, one turned 30 deg about the camera's y axis; corners in two cells.
TEST(IntrinsicsVerdict, CoverageAndTiltHandWorked) {
  IntrinsicsResult r;
  r.camera = synth::eurocLikeCamera();  // 752 x 480 -> 10 x 6 cells of 75.2 x 80 px
  ViewStats a, b;
  a.T_C_T.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  b.T_C_T.linear() = (Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                         .toRotationMatrix();
  r.views = {a, b};
  for (const Eigen::Vector2d& px : {Eigen::Vector2d(10, 10), Eigen::Vector2d(70, 70),
                                    Eigen::Vector2d(751, 479)}) {
    CornerResidual cr;
    cr.pixel = px;
    r.residuals.push_back(cr);
  }
  CornerResidual outlier;  // outliers do not count
  outlier.pixel = Eigen::Vector2d(400, 240);
  outlier.inlier = false;
  r.residuals.push_back(outlier);
  const IntrinsicsCoverage c = measureCoverage(r, 10);
  EXPECT_EQ(c.cells_x, 10);
  EXPECT_EQ(c.cells_y, 6);
  EXPECT_NEAR(c.image_share, 2.0 / 60, 1e-12);
  EXPECT_EQ(c.corners_per_cell[0], 2);
  EXPECT_EQ(c.corners_per_cell[59], 1);
  ASSERT_EQ(c.view_tilt_deg.size(), 2u);
  EXPECT_NEAR(c.view_tilt_deg[0], 0, 1e-9);
  EXPECT_NEAR(c.view_tilt_deg[1], 30, 1e-9);
  EXPECT_NEAR(c.tilt_spread_deg, 30, 1e-9);
  EXPECT_NEAR(c.max_tilt_deg, 30, 1e-9);
  EXPECT_NEAR(std::abs(c.view_tilt_xy_deg[1].y()), 30, 1e-9);  // about the camera's y axis
  EXPECT_NEAR(c.view_tilt_xy_deg[1].x(), 0, 1e-9);
}

class JudgedResult : public ::testing::Test {
 protected:
  void SetUp() override {
    const CalibCamera truth = synth::eurocLikeCamera();
    result_ = calibrateIntrinsics(synth::syntheticViews(truth, AprilGrid{}, 25, 0.2), 752, 480, options_);
    ASSERT_EQ(judgeIntrinsics(result_, options_).verdict.verdict, Verdict::kOk);
  }
  Verdict judge(const IntrinsicsResult& r) { return judgeIntrinsics(r, options_).verdict.verdict; }
  IntrinsicsOptions options_;
  IntrinsicsResult result_;
};

TEST_F(JudgedResult, EachPlausibilityCheckFails) {
  IntrinsicsResult r = result_;
  r.camera.params[2] = 800;  // principal point outside the 752-wide image
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.camera.params[0] = 5 * 752;  // on the bound of the plausible range
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.camera.params[1] = 0.2 * 752;
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.camera.params[5] = std::nan("");
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.rms_px = 12;  // > failed_rms_px
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r.rms_px = 2;   // > max_rms_px only
  EXPECT_EQ(judge(r), Verdict::kWeak);
  r = result_;
  r.corners_not_projected = 3;
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.final_solve_usable = false;
  r.solver_problems = {"distortion stage: the reprojection could not be evaluated"};
  EXPECT_EQ(judge(r), Verdict::kFailed);
  r = result_;
  r.camera.params[4] = -1.5;  // folds back within the covered radius
  r.camera.params[5] = 0;
  EXPECT_EQ(judge(r), Verdict::kFailed);
}

TEST_F(JudgedResult, WeakChecksAreOptions) {
  IntrinsicsVerdictOptions strict;
  strict.min_views = 30;  // 25 views
  const IntrinsicsJudgement j = judgeIntrinsics(result_, options_, strict);
  EXPECT_EQ(j.verdict.verdict, Verdict::kWeak);
  EXPECT_TRUE(j.verdict.has("views"));
  strict = {};
  strict.max_focal_rel_sigma = 1e-6;
  const IntrinsicsJudgement k = judgeIntrinsics(result_, options_, strict);
  EXPECT_TRUE(k.poorly_determined[0] && k.poorly_determined[1]);
  EXPECT_FALSE(k.poorly_determined[2]);
}

TEST(CalibrationVerdict, FormatsOkWeakAndFailed) {
  CalibrationVerdict v;
  EXPECT_EQ(formatVerdict(v, "x"), "Verdict: ok (every check passed)\n");
  EXPECT_EQ(verdictYamlComment(v), "# verdict: ok\n");
  v.add(Verdict::kWeak, "coverage", "40 % < 50 %", "fill the image");
  v.add(Verdict::kWeak, "tilt", "20 deg < 25 deg", "fill the image");  // advice once
  EXPECT_EQ(v.verdict, Verdict::kWeak);
  EXPECT_EQ(v.record_next.size(), 1u);
  const std::string text = formatVerdict(v, "camchain.yaml");
  EXPECT_NE(text.find("WARNING: verdict WEAK. camchain.yaml was written"), std::string::npos) << text;
  EXPECT_NE(text.find("[weak] coverage: 40 % < 50 %"), std::string::npos) << text;
  EXPECT_NE(text.find("Record next:\n  * fill the image"), std::string::npos) << text;
  const std::string yaml = verdictYamlComment(v);
  for (size_t at = 0; at < yaml.size(); at = yaml.find('\n', at) + 1) EXPECT_EQ(yaml[at], '#');
  EXPECT_NE(yaml.find("# verdict: weak"), std::string::npos);
  v.add(Verdict::kFailed, "plausibility", "fu at the bound");
  v.add(Verdict::kFailed, "residuals", "RMS 21 px > 5 px");
  EXPECT_EQ(v.verdict, Verdict::kFailed);
  // The one-line reason names the failed findings only, not the weak ones added before them.
  EXPECT_EQ(failureReasons(v), "fu at the bound; RMS 21 px > 5 px");
  EXPECT_NE(formatVerdict(v, "x").find("FAILED: verdict FAILED. Nothing was written"), std::string::npos);
  v.add(Verdict::kWeak, "views", "5 < 10");  // never lowers the verdict
  EXPECT_EQ(v.verdict, Verdict::kFailed);
}

}  // namespace
}  // namespace adugs::calib

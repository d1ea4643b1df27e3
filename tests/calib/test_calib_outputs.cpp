// Kalibr YAML, ViSP XML, the report and the residual plot.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <visp3/core/vpXmlParserCamera.h>
#include <yaml-cpp/yaml.h>

#include "calib/intrinsics/intrinsics_report.h"
#include "calib/intrinsics/visp_camera_xml.h"
#include "calib/kalibr_yaml.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(KalibrYaml, CamchainHasKalibrKeysAndExactNumbers) {
  const CalibCamera cam = synth::eurocLikeCamera();
  const YAML::Node n = YAML::Load(formatCamchainYaml(cam));
  const YAML::Node c = n["cam0"];
  ASSERT_TRUE(c);
  EXPECT_EQ(c["camera_model"].as<std::string>(), "pinhole");
  EXPECT_EQ(c["distortion_model"].as<std::string>(), "radtan");
  EXPECT_EQ(c["intrinsics"][0].as<double>(), 458.654);
  EXPECT_EQ(c["distortion_coeffs"][3].as<double>(), 1.76187114e-05);
  EXPECT_EQ(c["resolution"][0].as<int>(), 752);
  EXPECT_EQ(c["resolution"][1].as<int>(), 480);
  EXPECT_EQ(YAML::Load(formatCamchainYaml(synth::fisheyeCamera()))["cam0"]["distortion_model"]
                .as<std::string>(),
            "equidistant");
}

TEST(KalibrYaml, ImuYamlHasKalibrKeys) {
  ImuNoiseFigures f{0.002, 0.003, 1.6968e-04, 1.9393e-05, 200};
  const YAML::Node n = YAML::Load(formatImuYaml(f));
  EXPECT_EQ(n["accelerometer_noise_density"].as<double>(), 0.002);
  EXPECT_EQ(n["accelerometer_random_walk"].as<double>(), 0.003);
  EXPECT_EQ(n["gyroscope_noise_density"].as<double>(), 1.6968e-04);
  EXPECT_EQ(n["gyroscope_random_walk"].as<double>(), 1.9393e-05);
  EXPECT_EQ(n["update_rate"].as<double>(), 200);
  EXPECT_EQ(n["rostopic"].as<std::string>(), "/imu0");
}

TEST(VispCameraXml, ViSPReadsBackTheProjection) {
  test::TempDir tmp("adugs_visp_xml");
  const std::string path = (tmp / "camera.xml").string();
  writeVispCameraXml(path, synth::eurocLikeCamera());
  vpXmlParserCamera parser;
  vpCameraParameters cam;
  ASSERT_EQ(parser.parse(cam, path, "Camera", vpCameraParameters::perspectiveProjWithoutDistortion,
                         752, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_NEAR(cam.get_px(), 458.654, 1e-6);
  EXPECT_NEAR(cam.get_v0(), 248.375, 1e-6);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("ViSP cannot express this distortion"), std::string::npos);

  // Radial-only radtan: the with-distortion model is written too, kud = k1 exactly.
  CalibCamera radial = synth::eurocLikeCamera();
  radial.params = {400, 400, 320, 240, -0.2, 0, 0, 0};
  radial.width = 640;
  writeVispCameraXml(path, radial);
  vpXmlParserCamera parser2;
  ASSERT_EQ(parser2.parse(cam, path, "Camera", vpCameraParameters::perspectiveProjWithDistortion,
                          640, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_NEAR(cam.get_kud(), -0.2, 1e-12);
  EXPECT_GT(cam.get_kdu(), 0.0);  // the inverse of barrel distortion
}

TEST(CalibrationReport, ReportAndPlotDescribeTheResult) {
  const CalibCamera truth = synth::eurocLikeCamera();
  const auto views = synth::syntheticViews(truth, AprilGrid{}, 6, 0.2);
  const IntrinsicsResult r = calibrateIntrinsics(views, truth.width, truth.height, {});
  ReportContext ctx;
  ctx.input = "synthetic";
  ctx.target = "AprilGrid 6x6";
  ctx.has_reference = true;
  ctx.reference_name = "truth";
  ctx.reference = truth;
  ctx.reference_rms_px = reprojectionRmsWithFixedIntrinsics(views, truth);
  EXPECT_NEAR(ctx.reference_rms_px, 0.2 * std::sqrt(2.0), 0.05);  // the injected noise
  const IntrinsicsJudgement j = judgeIntrinsics(r, IntrinsicsOptions{});
  const std::string report = formatIntrinsicsReport(r, j, ctx);
  EXPECT_NE(report.find("Compared with truth"), std::string::npos);
  EXPECT_NE(report.find("pinhole-radtan"), std::string::npos);
  EXPECT_NE(report.find("rms"), std::string::npos);
  EXPECT_NE(report.find("Per view"), std::string::npos);
  // 6 views < 10: weak, said in the report with what to record next.
  EXPECT_EQ(j.verdict.verdict, Verdict::kWeak);
  EXPECT_NE(report.find("WARNING: verdict WEAK"), std::string::npos) << report;
  EXPECT_NE(report.find("Record next"), std::string::npos) << report;
  EXPECT_NE(report.find("Coverage"), std::string::npos) << report;
  const cv::Mat plot = renderResidualPlot(r);
  EXPECT_EQ(plot.type(), CV_8UC3);
  EXPECT_GT(cv::countNonZero(plot.reshape(1) < 250), 1000);  // something was drawn
  const cv::Mat coverage = renderCoveragePlot(r, j);
  EXPECT_EQ(coverage.type(), CV_8UC3);
  EXPECT_GT(cv::countNonZero(coverage.reshape(1) < 250), 1000);
}

}  // namespace
}  // namespace adugs::calib

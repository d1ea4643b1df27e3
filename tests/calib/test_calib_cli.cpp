// End-to-end: the `adugs calib ...` commands (skipped when the adugs binary was not built).
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "calib/target/aprilgrid_target_yaml.h"
#include "calib/target/corner_csv.h"
#include "tests/calib/camera_imu_synthetic.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {
namespace fs = std::filesystem;

#define REQUIRE_ADUGS()                                                              \
  do {                                                                               \
    if (!fs::exists(ADUGS_BINARY)) ADUGS_SKIP_OR_FAIL("adugs not built at " << ADUGS_BINARY); \
  } while (0)

TEST(CalibCli, TargetWritesPngPdfAndYaml) {
  REQUIRE_ADUGS();
  test::TempDir tmp("adugs_calib_cli");
  std::string out;
  const std::string prefix = (tmp / "board").string();
  ASSERT_EQ(test::runAdugs("calib target --tag-rows 3 --tag-cols 4 --tag-size 0.05 "
                           "--tag-spacing 0.3 --dpi 150 --out " + prefix, &out), 0) << out;
  const cv::Mat png = cv::imread(prefix + ".png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(png.empty());
  // 4 * 0.065 m + 2 cm margins ... at 150 dpi.
  EXPECT_NEAR(png.cols, (4 * 0.065 + 0.015 + 0.04) / 0.0254 * 150, 2);
  EXPECT_TRUE(fs::file_size(prefix + ".pdf") > 1000);
  const AprilGrid g = readAprilGridYaml(prefix + ".yaml");
  EXPECT_EQ(g.tag_cols, 4);
  // Inconsistent target: a clear error and a non-zero exit.
  test::writeText(tmp / "bad.yaml", "target_type: aprilgrid\ntagRows: 6\ntagCols: 6\n");
  EXPECT_NE(test::runAdugs("calib target --target " + (tmp / "bad.yaml").string(), &out), 0);
  EXPECT_NE(out.find("tagSize"), std::string::npos) << out;
}

TEST(CalibCli, IntrinsicsFromEurocCornerCsvs) {
  REQUIRE_ADUGS();
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "cam_april" / "cam0";
  ADUGS_REQUIRE_SHARED(dir);
  test::TempDir tmp("adugs_calib_cli");
  std::string out;
  const auto reference = test::sharedDataDir() / "euroc_v101_micro" / "mav0" / "cam0" / "sensor.yaml";
  const std::string compare =
      fs::exists(reference) ? " --reference " + reference.string() : std::string();
  ASSERT_EQ(test::runAdugs("calib intrinsics --corners " + dir.string() +
                               " --resolution 752x480 --model radtan --out " +
                               tmp.path().string() + compare,
                           &out),
            0)
      << out;
  if (!compare.empty()) {
    EXPECT_NE(out.find("Compared with"), std::string::npos) << out;
    EXPECT_NE(out.find("reference 0.29"), std::string::npos) << out;  // published: 0.295 px
  }
  const YAML::Node cam = YAML::LoadFile((tmp / "camchain.yaml").string())["cam0"];
  EXPECT_NEAR(cam["intrinsics"][0].as<double>(), 458.654, 0.025 * 458.654);
  EXPECT_TRUE(fs::exists(tmp / "camera.xml"));
  EXPECT_TRUE(fs::exists(tmp / "report.txt"));
  EXPECT_FALSE(cv::imread((tmp / "residuals.png").string()).empty());
  EXPECT_FALSE(cv::imread((tmp / "coverage.png").string()).empty());
  EXPECT_GT(fs::file_size(tmp / "residuals.csv"), 3728u * 30);  // one row per corner
  // These 30 views are weak (issue 18): written, with the warning on stdout, in the report, as
  // comments in the YAML and the XML, and no solver log lines.
  EXPECT_NE(out.find("WARNING: verdict WEAK"), std::string::npos) << out;
  EXPECT_NE(out.find("Record next"), std::string::npos) << out;
  EXPECT_EQ(out.find("Terminating"), std::string::npos) << out;
  EXPECT_EQ(out.find("trust_region"), std::string::npos) << out;
  std::string yaml, report, xml;
  test::runCommand("cat " + (tmp / "camchain.yaml").string(), &yaml);
  test::runCommand("cat " + (tmp / "report.txt").string(), &report);
  test::runCommand("cat " + (tmp / "camera.xml").string(), &xml);
  EXPECT_EQ(yaml.rfind("# verdict: weak\n# WARNING", 0), 0u) << yaml;
  EXPECT_NE(report.find("WARNING: verdict WEAK"), std::string::npos);
  EXPECT_NE(xml.find("# verdict: weak"), std::string::npos) << xml;
}

// A camera held still, board face-on (issue 18's weak case, synthetic: see
// IntrinsicsCalibrator.NearStillViewsAreNeverOk): the focal length is not determined, so the
// verdict is failed: exit code 3, the reason printed, no calibration file written.
TEST(CalibCli, UndeterminedFocalFailsWithExitThreeAndWritesNothing) {
  REQUIRE_ADUGS();
  test::TempDir tmp("adugs_calib_cli");
  CalibCamera cam1 = synth::eurocLikeCamera();
  cam1.params = {457.587, 456.134, 379.999, 255.238, -0.28368365, 0.07451284, -0.00010473, -3.555e-05};
  const AprilGrid grid = synth::eurocGrid();
  fs::create_directories(tmp / "corners");
  for (const auto& v : synth::nearStillViews(cam1, grid, 30, 0.2, 2, 1.1, 0, 0.002, 0.1))
    writeCornerCsv((tmp / "corners" / (std::to_string(1000000000000 + v.t_ns) + ".csv")).string(),
                   grid, v);
  std::string out;
  const std::string dir = (tmp / "out").string();
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + (tmp / "corners").string() +
                               " --resolution 752x480 --out " + dir,
                           &out),
            3)
      << out;
  EXPECT_NE(out.find("FAILED: verdict FAILED. Nothing was written"), std::string::npos) << out;
  EXPECT_NE(out.find("adugs: calibration failed:"), std::string::npos) << out;
  EXPECT_NE(out.find("do not determine the focal length"), std::string::npos) << out;
  EXPECT_EQ(out.find("Terminating"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/camchain.yaml"));
  EXPECT_FALSE(fs::exists(dir + "/camera.xml"));
}

TEST(CalibCli, BadInputsFailWithAClearMessage) {
  REQUIRE_ADUGS();
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "cam_april" / "cam0";
  ADUGS_REQUIRE_SHARED(dir);
  test::TempDir tmp("adugs_calib_cli");
  std::string out;
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + dir.string() +
                               " --resolution 752x480 --model kb8 --out " + tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("unknown camera model 'kb8'"), std::string::npos) << out;
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + dir.string() + " --out " +
                               tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("--resolution"), std::string::npos) << out;
  // A misspelt verdict bound is named, not ignored.
  test::writeText(tmp / "o.yaml", "verdict:\n  max_focal_rel_sigmaa: 0.01\n");
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + dir.string() + " --resolution 752x480 --options " +
                               (tmp / "o.yaml").string() + " --out " + tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("verdict.max_focal_rel_sigmaa"), std::string::npos) << out;
  // Too few views: keep two of the CSVs.
  fs::create_directories(tmp / "two");
  int copied = 0;
  for (const auto& e : fs::directory_iterator(dir))
    if (copied++ < 2) fs::copy_file(e.path(), tmp / "two" / e.path().filename());
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + (tmp / "two").string() +
                               " --resolution 752x480 --out " + tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("too few views"), std::string::npos) << out;
  // A broken --reference is named before any calibration work (ahead of the too-few-views error).
  test::writeText(tmp / "ref.yaml", "sensor_type: camera\n");
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + (tmp / "two").string() + " --resolution 752x480 --reference " +
                               (tmp / "ref.yaml").string() + " --out " + tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("ref.yaml"), std::string::npos) << out;
  EXPECT_EQ(out.find("too few views"), std::string::npos) << out;
  // Target YAML disagreeing with the CSVs.
  test::writeText(tmp / "t.yaml", "target_type: aprilgrid\ntagRows: 6\ntagCols: 6\n"
                                  "tagSize: 0.1\ntagSpacing: 0.3\n");
  EXPECT_EQ(test::runAdugs("calib intrinsics --corners " + dir.string() + " --target " +
                               (tmp / "t.yaml").string() + " --resolution 752x480 --out " +
                               tmp.path().string(),
                           &out),
            2);
  EXPECT_NE(out.find("tag_size"), std::string::npos) << out;
}

TEST(CalibCli, IntrinsicsFromTheRealImageFolderNeedsMoreViews) {
  REQUIRE_ADUGS();
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "stereo";
  ADUGS_REQUIRE_SHARED(dir);
  test::TempDir tmp("adugs_calib_cli");
  std::string out;
  // Detection works on the one real image, but one view cannot calibrate a camera.
  ASSERT_EQ(test::runAdugs("calib detect --target " +
                               (test::sharedDataDir() / "euroc_calib_aprilgrid" / "aprilgrid" /
                                "target.yaml").string() +
                               " --images " + dir.string() + " --out " + (tmp / "det").string(),
                           &out),
            0)
      << out;
  EXPECT_NE(out.find("144 corners"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(tmp / "det" / "1403709395937837056.csv"));
}

}  // namespace
}  // namespace adugs::calib

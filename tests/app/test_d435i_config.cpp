// data/config/d435i.yaml: a run config that `adugs run` accepts (its tracker and estimator settings
// on a simulated 30 Hz camera with a 400 Hz IMU, as the D435i gives them), and whose d435i: map
// is checked strictly like every other map.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "data/formats/trajectory_io.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace {

const std::string kConfig = std::string(ADUGS_SOURCE_DIR) + "/data/config/d435i.yaml";

TEST(D435iConfig, LoadsInAdugsRunOnA30HzSequenceWithA400HzImu) {
  TempDir dir("adugs_d435i_config");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene room --motion handheld --level none --seed 3 --duration 4 --rate 30 --imu-rate 400 --out " +
                         (dir / "seq").string(),
                     &log),
            0)
      << log;
  ASSERT_EQ(runAdugs("run -q " + (dir / "seq").string() + " --config " + kConfig + " --out " + (dir / "out").string(), &log), 0)
      << log;
  const std::string summary = readFile(dir / "out" / "summary.yaml");
  EXPECT_NE(summary.find("resets: 0"), std::string::npos) << summary;
  EXPECT_NE(summary.find("time_offset_estimated: true"), std::string::npos) << summary;  // on in the D435i config
  const auto traj = data::readTrajectory((dir / "out" / "trajectory.tum").string());
  EXPECT_GT(traj.size(), 60u);  // 120 frames, initialised within 2 s
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("ate_se3_rmse_m: ([0-9.e-]+)"))) << summary;
  EXPECT_LT(std::stod(m[1]), 0.05) << summary;  // measured 0.001 m on this sequence
}

TEST(D435iConfig, BadD435iKeysAreErrorsNamingFileLineAndKey) {
  TempDir dir("adugs_d435i_config");
  const auto check = [&](const std::string& yaml, const std::string& needle) {
    writeText(dir / "bad.yaml", yaml);
    std::string log;
    EXPECT_EQ(runAdugs("run -q " + (dir / "nothing").string() + " --config " + (dir / "bad.yaml").string() +
                           " --out " + (dir / "out").string(),
                       &log),
              2)
        << log;
    EXPECT_NE(log.find("bad.yaml:"), std::string::npos) << log;
    EXPECT_NE(log.find(needle), std::string::npos) << log;
  };
  check("d435i:\n  emiter: off\n", "d435i.emiter");
  check("d435i:\n  stream: depth\n", "d435i.stream");
  check("d435i:\n  fps: 0\n", "d435i.fps");
  check("d435i:\n  gain: 64\n", "manual exposure");
  check("d435i:\n  cam0:\n    camera_model: pinhole\n    intrinsics: [1, 2, 3, 4]\n    distortion_model: radtan\n"
        "    distortion_coeffs: [0, 0, 0, 0]\n    resolution: [848]\n",
        "d435i.cam0.resolution");
  check("d435i:\n  imu0:\n    accelerometer_noise_density: 0.01\n", "d435i.imu0.accelerometer_random_walk");
}

}  // namespace
}  // namespace adugs::test

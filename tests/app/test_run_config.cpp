// The run config without --config: one per sensor class in data/config/, built into the binary and
// chosen from the sequence's camera rate and model (app/run_config.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "app/run_config.h"
#include "data/builtin_config.h"
#include "data/formats/trajectory_io.h"
#include "data/sources/dataset_preset.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace {
namespace fs = std::filesystem;

data::CameraCalibration camera(double rate_hz, std::vector<double> distortion) {
  data::CameraCalibration c;
  c.width = 752;
  c.height = 480;
  c.fx = c.fy = 460;
  c.cx = 376;
  c.cy = 240;
  c.rate_hz = rate_hz;
  c.distortion = std::move(distortion);
  return c;
}

TEST(RunConfigChoice, SensorClassFromRateAndDistortion) {
  const std::vector<double> radtan{-0.28, 0.07, 2e-4, 2e-5}, none{0, 0, 0, 0};
  EXPECT_EQ(app::chooseRunConfig(camera(20, radtan), data::SimFolder::kNone).name, "euroc.yaml");  // EuRoC cam0
  EXPECT_EQ(app::chooseRunConfig(camera(20, none), data::SimFolder::kNone).name, "sim.yaml");      // adugs sim, VIODE
  EXPECT_EQ(app::chooseRunConfig(camera(30, none), data::SimFolder::kNone).name, "d435i.yaml");    // D435i IR, OpenLORIS
  EXPECT_EQ(app::chooseRunConfig(camera(30, radtan), data::SimFolder::kNone).name, "d435i.yaml");
  data::CameraCalibration fisheye = camera(20, none);  // TUM-VI: equidistant, a real lens
  fisheye.distortion_model = data::DistortionModel::kEquidistant;
  EXPECT_EQ(app::chooseRunConfig(fisheye, data::SimFolder::kNone).name, "euroc.yaml");
  EXPECT_EQ(app::chooseRunConfig(camera(24.9, none), data::SimFolder::kNone).name, "sim.yaml");    // the boundary: 25 Hz
  EXPECT_EQ(app::chooseRunConfig(camera(25, none), data::SimFolder::kNone).name, "d435i.yaml");
  // Unknown rate (a bag with one image): the EuRoC class, and the reason says so.
  const app::RunConfigChoice unknown = app::chooseRunConfig(camera(0, none), data::SimFolder::kNone);
  EXPECT_EQ(unknown.name, "euroc.yaml");
  EXPECT_NE(unknown.reason.find("rate unknown"), std::string::npos) << unknown.reason;
  // A folder of `adugs sim` has EuRoC's lens distortion (and may run at 30 Hz): the folder tells.
  EXPECT_EQ(app::chooseRunConfig(camera(20, radtan), data::SimFolder::kSynthetic).name, "sim.yaml");
  EXPECT_EQ(app::chooseRunConfig(camera(30, radtan), data::SimFolder::kSynthetic).name, "sim.yaml");
  // A hybrid folder (rendered images along a real flight's IMU) below 25 Hz takes the real IMU's
  // class, with or without lens distortion in its renders; at 30 Hz the D435i's, as any camera.
  EXPECT_EQ(app::chooseRunConfig(camera(20, none), data::SimFolder::kHybrid).name, "euroc.yaml");
  EXPECT_EQ(app::chooseRunConfig(camera(20, radtan), data::SimFolder::kHybrid).name, "euroc.yaml");
  EXPECT_EQ(app::chooseRunConfig(camera(30, none), data::SimFolder::kHybrid).name, "d435i.yaml");
}

data::OpenedSequence sequenceWith(const data::CameraCalibration& c) {
  data::OpenedSequence s;
  s.camera = c;
  return s;
}

// The built-in texts are the files of data/config/ byte for byte, and each loads into the values
// the file states (a broken embedding or a reader change would fail here, not in a user's run).
TEST(RunConfigChoice, BuiltInConfigsAreTheFilesOfDataConfig) {
  const fs::path dir = fs::path(ADUGS_SOURCE_DIR) / "data" / "config";
  for (const char* name : {"euroc.yaml", "sim.yaml", "d435i.yaml", "presets/tum-vi/imu.yaml"})
    EXPECT_EQ(data::builtinConfigText(name), readFile(dir / name)) << name;
  EXPECT_EQ(data::builtinConfigText("nothing.yaml"), "");

  const std::vector<double> radtan{-0.28, 0.07, 2e-4, 2e-5}, none{0, 0, 0, 0};
  for (const auto& [cam, file] : {std::pair{camera(20, radtan), "euroc.yaml"}, std::pair{camera(20, none), "sim.yaml"},
                                  std::pair{camera(30, none), "d435i.yaml"}}) {
    std::string described;
    const app::RunConfig built_in = app::runConfigFor("", sequenceWith(cam), &described);
    const app::RunConfig from_file = app::loadRunConfig((dir / file).string());
    EXPECT_EQ(described.rfind(std::string("data/config/") + file + " (built in; ", 0), 0u) << described;
    EXPECT_EQ(built_in.estimator.window_size, from_file.estimator.window_size) << file;
    EXPECT_EQ(built_in.estimator.outlier_reprojection_px, from_file.estimator.outlier_reprojection_px) << file;
    EXPECT_EQ(built_in.estimator.estimate_time_offset, from_file.estimator.estimate_time_offset) << file;
    EXPECT_EQ(built_in.tracker.max_features, from_file.tracker.max_features) << file;
  }
  // The classes differ where the files do (else the choice would be for nothing).
  std::string d;
  EXPECT_TRUE(app::runConfigFor("", sequenceWith(camera(30, none)), &d).estimator.estimate_time_offset);
  EXPECT_FALSE(app::runConfigFor("", sequenceWith(camera(20, radtan)), &d).estimator.estimate_time_offset);
  EXPECT_EQ(app::runConfigFor("", sequenceWith(camera(20, none)), &d).estimator.outlier_reprojection_px, 1.5);
  EXPECT_EQ(app::runConfigFor("", sequenceWith(camera(20, radtan)), &d).estimator.outlier_reprojection_px, 3.0);
}

// A bag written by a real recorder (realsense-ros on a T265, third-party): the Kalibr file gives
// no rate, so the camera's rate comes from the image topic's record times (30 Hz) and the D435i
// class (30 Hz settings, time offset online) is chosen.
TEST(RunConfigChoice, ARealRecordersBagGetsItsRateFromTheImageTopicAndItsClass) {
  const fs::path bag = sharedDataDir() / "rosbags/kapture_t265/trimmed_locoffice.bag";
  ADUGS_REQUIRE_SHARED(bag);
  TempDir dir("adugs_run_config");
  writeText(dir / "camchain.yaml",
            "cam0:\n  camera_model: pinhole\n  intrinsics: [286.0, 286.0, 424.0, 400.0]\n"
            "  distortion_model: equidistant\n  distortion_coeffs: [-0.01, 0.05, -0.05, 0.01]\n"
            "  resolution: [848, 800]\n  T_cam_imu:\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n"
            "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n");
  writeText(dir / "imu.yaml", data::builtinConfigText("presets/euroc/imu.yaml"));
  data::PlaybackOptions o;
  o.dataset = "bag";
  o.path = bag.string();
  o.topics.image = "/camera/fisheye1/image_raw";
  o.topics.accel = "/camera/accel/sample";
  o.topics.gyro = "/camera/gyro/sample";
  o.calibration = {(dir / "camchain.yaml").string(), (dir / "imu.yaml").string()};
  const data::OpenedSequence sequence = data::openSequence(o, dir.path().string());
  EXPECT_NEAR(sequence.camera.rate_hz, 30.0, 1.5);
  std::string described;
  app::runConfigFor("", sequence, &described);
  EXPECT_EQ(described.rfind("data/config/d435i.yaml (built in; 30.5 Hz camera", 0), 0u) << described;
}

// A user's --config wins, and is what the summary names.
TEST(RunConfigChoice, TheUsersConfigWins) {
  TempDir dir("adugs_run_config");
  writeText(dir / "mine.yaml", "estimator:\n  window_size: 12\n");
  std::string described;
  const app::RunConfig c = app::runConfigFor((dir / "mine.yaml").string(), sequenceWith(camera(30, {0, 0, 0, 0})), &described);
  EXPECT_EQ(c.estimator.window_size, 12);
  EXPECT_EQ(described, (dir / "mine.yaml").string());
}

// End to end: `adugs run` says which config it took, at the start and in the summary: a folder of
// `adugs sim` takes the simulator's; the same 30 Hz images with a real IMU (a hybrid folder) the
// D435i class's, with the time offset estimated online.
TEST(RunConfigChoice, AdugsRunPrintsAndRecordsTheChosenConfig) {
  TempDir dir("adugs_run_config");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene room --level none --seed 2 --duration 4 --rate 30 --out " + (dir / "seq30").string(), &log), 0)
      << log;
  ASSERT_EQ(runAdugs("run " + (dir / "seq30").string() + " --out " + (dir / "sim").string(), &log), 0) << log;
  EXPECT_NE(log.find("run: config data/config/sim.yaml (built in; written by adugs sim with a simulated IMU"), std::string::npos) << log;
  EXPECT_NE(readFile(dir / "sim" / "summary.yaml").find("config: \"data/config/sim.yaml (built in;"), std::string::npos);

  // The same folder as a hybrid one (rendered images along a real IMU's flight) goes by its camera.
  const fs::path sim_yaml = dir / "seq30" / "mav0" / "sim.yaml";
  std::string text = readFile(sim_yaml);
  ASSERT_NE(text.find("\nmode: synthetic\n"), std::string::npos) << text;
  writeText(sim_yaml, text.replace(text.find("\nmode: synthetic\n"), 17, "\nmode: hybrid\n"));
  ASSERT_EQ(runAdugs("run " + (dir / "seq30").string() + " --out " + (dir / "out").string(), &log), 0) << log;
  EXPECT_NE(log.find("run: config data/config/d435i.yaml (built in; 30 Hz camera"), std::string::npos) << log;
  const std::string summary = readFile(dir / "out" / "summary.yaml");
  EXPECT_NE(summary.find("config: \"data/config/d435i.yaml (built in;"), std::string::npos) << summary;
  EXPECT_NE(summary.find("time_offset_estimated: true"), std::string::npos) << summary;
  EXPECT_GT(data::readTrajectory((dir / "out" / "trajectory.tum").string()).size(), 60u);

  // Below 25 Hz without lens distortion a hybrid folder is still a real IMU's: the EuRoC class,
  // whose accelerometer density is the calibration's times its accel_noise_inflation (4).
  const fs::path cam_yaml = dir / "seq30" / "mav0" / "cam0" / "sensor.yaml";
  std::string cam = readFile(cam_yaml);
  cam = std::regex_replace(cam, std::regex("\nrate_hz: [0-9.]+"), "\nrate_hz: 20");
  cam = std::regex_replace(cam, std::regex("\ndistortion_coefficients: \\[[^\\]]*\\]"),
                           "\ndistortion_coefficients: [0.0, 0.0, 0.0, 0.0]");
  writeText(cam_yaml, cam);
  ASSERT_EQ(runAdugs("run " + (dir / "seq30").string() + " --out " + (dir / "euroc").string(), &log), 0) << log;
  EXPECT_NE(log.find("run: config data/config/euroc.yaml (built in; 20 Hz camera rendered along a real flight"),
            std::string::npos)
      << log;
  const std::string euroc_summary = readFile(dir / "euroc" / "summary.yaml");
  EXPECT_NE(euroc_summary.find("accel_noise_density: 0.008  # m/s^2/sqrt(Hz) in the preintegration: the IMU "
                               "calibration's 0.002 x accel_noise_inflation 4"),
            std::string::npos)
      << euroc_summary;

  // A sim.yaml that is not YAML is an input error naming it, not a silent guess of the class.
  writeText(sim_yaml, "mode: [synthetic\n");
  EXPECT_EQ(runAdugs("run -q " + (dir / "seq30").string() + " --out " + (dir / "bad").string(), &log), 2) << log;
  EXPECT_NE(log.find("sim.yaml"), std::string::npos) << log;
}

}  // namespace
}  // namespace adugs::test

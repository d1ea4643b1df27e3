// adugs calib show | convert on files of other tools, and --calibration on adugs run: exit codes,
// messages, and what the files written for each tool read back as.
#include <gtest/gtest.h>

#include <filesystem>

#include "data/formats/calibration_files.h"
#include "data/formats/yaml_options.h"
#include "tests/test_support.h"

namespace adugs {
namespace {
namespace fs = std::filesystem;
using test::runAdugs;
using test::TempDir;
using test::writeText;

const char* kCamchain =
    "%YAML:1.0\ncam0:\n  T_imu_cam:\n    - [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975]\n"
    "    - [0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768]\n"
    "    - [-0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949]\n    - [0.0, 0.0, 0.0, 1.0]\n"
    "  cam_overlaps: [1]\n  camera_model: pinhole\n  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
    "  distortion_model: radtan\n  intrinsics: [458.654, 457.296, 367.215, 248.375]\n  resolution: [752, 480]\n"
    "  rostopic: /cam0/image_raw\n";
const char* kImu =
    "%YAML:1.0\nimu0:\n  accelerometer_noise_density: 2.0000e-3\n  accelerometer_random_walk: 3.0000e-3\n"
    "  gyroscope_noise_density: 1.6968e-04\n  gyroscope_random_walk: 1.9393e-05\n  rostopic: /imu0\n"
    "  update_rate: 200.0\n  model: kalibr\n";

TEST(CmdCalibFiles, ShowPrintsAndWritesTheJsonLayout) {
  TempDir dir;
  writeText(dir / "chain.yaml", kCamchain);
  writeText(dir / "imu.yaml", kImu);
  std::string out;
  ASSERT_EQ(runAdugs("calib show " + (dir / "chain.yaml").string() + " " + (dir / "imu.yaml").string() +
                         " --json " + (dir / "calib.json").string(),
                     &out),
            0)
      << out;
  EXPECT_NE(out.find("fx fy cx cy: 458.654 457.296 367.215 248.375"), std::string::npos) << out;
  EXPECT_NE(out.find("gyroscope noise density:     0.00016968"), std::string::npos) << out;
  const YAML::Node j = data::loadYamlFile((dir / "calib.json").string());
  EXPECT_EQ(j["cameras"][0]["model"].as<std::string>(), "pinhole");
  EXPECT_EQ(j["cameras"][0]["T_imu_cam"][1][3].as<double>(), -0.064676986768);
  EXPECT_EQ(j["imu"]["update_rate_hz"].as<double>(), 200.0);
  EXPECT_EQ(j["files"][1]["format"].as<std::string>(), "Kalibr imu");
}

TEST(CmdCalibFiles, BadInputIsNamedWithExitTwo) {
  TempDir dir;
  writeText(dir / "options.yaml", "max_features: 150\n");
  std::string out;
  EXPECT_EQ(runAdugs("calib show " + (dir / "options.yaml").string(), &out), 2) << out;
  EXPECT_NE(out.find("options.yaml"), std::string::npos) << out;
  EXPECT_NE(out.find("not a calibration file"), std::string::npos) << out;
  // A DS camera has no VINS camera file: refused, naming the field, nothing written.
  writeText(dir / "ds.json",
            "{\"value0\": {\"T_imu_cam\": [{\"px\": 0, \"py\": 0, \"pz\": 0, \"qx\": 0, \"qy\": 0, \"qz\": 0, \"qw\": 1}],"
            " \"intrinsics\": [{\"camera_type\": \"ds\", \"intrinsics\": {\"fx\": 349.7, \"fy\": 348.7, \"cx\": 365.8,"
            " \"cy\": 249.3, \"xi\": -0.24, \"alpha\": 0.567}}], \"resolution\": [[752, 480]], \"imu_update_rate\": 200.0,"
            " \"accel_noise_std\": [0.016, 0.016, 0.016], \"gyro_noise_std\": [0.000282, 0.000282, 0.000282],"
            " \"accel_bias_std\": [0.001, 0.001, 0.001], \"gyro_bias_std\": [0.0001, 0.0001, 0.0001]}}\n");
  EXPECT_EQ(runAdugs("calib convert " + (dir / "ds.json").string() + " --to vins --out " + (dir / "vins").string(), &out), 2)
      << out;
  EXPECT_NE(out.find("cam0.camera_model"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "vins" / "config.yaml"));
  // VINS' per-sample noise: show needs --imu-rate for densities; convert refuses without it.
  writeText(dir / "cam.yaml", "%YAML:1.0\n---\nmodel_type: PINHOLE\nimage_width: 640\nimage_height: 480\n"
                              "distortion_parameters:\n   k1: 0\n   k2: 0\n   p1: 0\n   p2: 0\n"
                              "projection_parameters:\n   fx: 400\n   fy: 400\n   cx: 320\n   cy: 240\n");
  writeText(dir / "vins.yaml", "%YAML:1.0\nimu: 1\nnum_of_cam: 1\ncam0_calib: \"cam.yaml\"\nbody_T_cam0: !!opencv-matrix\n"
                               "   rows: 4\n   cols: 4\n   dt: d\n   data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
                               "acc_n: 0.1\ngyr_n: 0.01\nacc_w: 0.001\ngyr_w: 0.0001\n");
  EXPECT_EQ(runAdugs("calib convert " + (dir / "vins.yaml").string() + " --to kalibr --out " + (dir / "k").string(), &out), 2)
      << out;
  EXPECT_NE(out.find("--imu-rate"), std::string::npos) << out;
  ASSERT_EQ(runAdugs("calib convert " + (dir / "vins.yaml").string() + " --imu-rate 400 --to kalibr --out " +
                         (dir / "k").string(),
                     &out),
            0)
      << out;
  const data::RigCalibration k =
      data::readCalibrationFiles({(dir / "k/camchain-imucam.yaml").string(), (dir / "k/imu.yaml").string()});
  EXPECT_NEAR(k.imu.noise.accel_noise_density, 0.1 / 20, 1e-15);  // 0.1 / sqrt(400 Hz)
  EXPECT_EQ(k.imu.noise.rate_hz, 400);
}

// What `convert` writes for each tool reads back as the same calibration (through the CLI).
TEST(CmdCalibFiles, ConvertToEveryToolReadsBackTheSame) {
  TempDir dir;
  writeText(dir / "chain.yaml", kCamchain);
  writeText(dir / "imu.yaml", kImu);
  const std::string in = (dir / "chain.yaml").string() + " " + (dir / "imu.yaml").string();
  const data::RigCalibration ref = data::readCalibrationFiles({(dir / "chain.yaml").string(), (dir / "imu.yaml").string()});
  std::string out;
  EXPECT_EQ(runAdugs("calib convert " + in + " --to basalt --out " + (dir / "basalt").string(), &out), 2) << out;
  EXPECT_NE(out.find("Basalt has no pinhole camera with radial-tangential distortion"), std::string::npos) << out;
  for (const std::string tool : {"kalibr", "openvins", "vins"}) {
    SCOPED_TRACE(tool);
    const fs::path folder = dir / tool;
    ASSERT_EQ(runAdugs("calib convert " + in + " --to " + tool + " --out " + folder.string(), &out), 0) << out;
    std::vector<std::string> files;
    if (tool == "kalibr") files = {(folder / "camchain-imucam.yaml").string(), (folder / "imu.yaml").string()};
    if (tool == "openvins") files = {(folder / "kalibr_imucam_chain.yaml").string(), (folder / "kalibr_imu_chain.yaml").string()};
    if (tool == "vins") files = {(folder / "config.yaml").string()};
    data::RigCalibration back = data::readCalibrationFiles(files);
    if (back.imu.noise_per_sample) data::resolvePerSampleNoise(back.imu, 200);
    ASSERT_EQ(back.cameras.size(), 1u);
    const data::CameraCalibration &a = ref.cameras[0].camera, &b = back.cameras[0].camera;
    EXPECT_NEAR(a.fx, b.fx, 1e-9);
    EXPECT_EQ(a.distortion, b.distortion);
    EXPECT_LT((a.T_B_C.matrix() - b.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(back.imu.noise.gyro_random_walk, 1.9393e-05, 1e-15);
  }
}

}  // namespace
}  // namespace adugs

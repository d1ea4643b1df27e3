// adugs calib show | convert on files of other tools, and --calibration on adugs run: exit codes,
// messages, and what the files written for each tool read back as.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "data/formats/calibration_files.h"
#include "data/formats/csv_reader.h"
#include "data/formats/trajectory_io.h"
#include "data/formats/yaml_options.h"
#include "tests/test_support.h"

namespace adugs {
namespace {
namespace fs = std::filesystem;
using test::readFile;
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
  EXPECT_NE(out.find("--model ds"), std::string::npos) << out;
  // The same lens refit as a double sphere: written, and read back as that DS.
  ASSERT_EQ(runAdugs("calib convert " + in + " --to basalt --model ds --max-refit-rms 2 --out " + (dir / "basalt").string(),
                     &out),
            0)
      << out;
  EXPECT_NE(out.find("cam0: radtan -> ds: RMS"), std::string::npos) << out;
  const data::RigCalibration ds = data::readCalibrationFiles({(dir / "basalt" / "calib.json").string()});
  EXPECT_EQ(ds.cameras[0].camera.projection, data::ProjectionModel::kDoubleSphere);
  EXPECT_NEAR(ds.cameras[0].camera.fx / (1 + ds.cameras[0].camera.projection_params[0]), 458.654, 0.02 * 458.654);  // on-axis focal
  // EuRoC's radtan corners are about 1 px RMS from any DS: the default limit (0.5 px) refuses it, naming the field.
  EXPECT_EQ(runAdugs("calib convert " + in + " --to basalt --model ds --out " + (dir / "basalt2").string(), &out), 2)
      << out;
  EXPECT_NE(out.find("cam0.camera_model"), std::string::npos) << out;
  EXPECT_NE(out.find("cannot hold this radtan lens"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "basalt2" / "calib.json"));
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

// `adugs run --calibration` on a simulated sequence: its own calibration given back through other
// tools' files gives the trajectory of the run without them; IMU intrinsics are applied to the
// samples (a sequence whose accelerometer x reads 3 % high runs like the original once Ta says so).
class CmdRunCalibration : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("adugs_run_calibration");
    std::string log;
    ASSERT_EQ(runAdugs("sim --scene room --level none --seed 3 --duration 8 --out " + (dir_->path() / "seq").string(), &log), 0)
        << log;
    // Solves converged to 1e-6 (the default stops at 1e-4): these runs differ from the reference
    // by rounding in their inputs (numbers through files), which an early stop turns into ~1 mm
    // (which step ends a solve moves), a converged solve into < 1e-6 m.
    writeText(dir_->path() / "cfg.yaml", "estimator:\n  solver_function_tolerance: 1.0e-6\n");
    ASSERT_EQ(runAdugs("run -q " + (dir_->path() / "seq").string() + cfg() + " --out " + (dir_->path() / "ref").string(), &log), 0)
        << log;
  }
  static std::string cfg() { return " --config " + (dir_->path() / "cfg.yaml").string(); }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path seq() { return dir_->path() / "seq"; }
  // Largest position difference to the reference run, over the same stamps.
  static double maxDifference(const fs::path& trajectory) {
    const data::Trajectory a = data::readTrajectory((dir_->path() / "ref/trajectory.tum").string());
    const data::Trajectory b = data::readTrajectory(trajectory.string());
    EXPECT_EQ(a.size(), b.size());
    double d = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
      EXPECT_EQ(a[i].t_ns, b[i].t_ns);
      d = std::max(d, (a[i].p_W_B - b[i].p_W_B).norm());
    }
    return d;
  }
  static TempDir* dir_;
};
TempDir* CmdRunCalibration::dir_ = nullptr;

TEST_F(CmdRunCalibration, TheSequencesOwnCalibrationThroughOtherToolsFilesGivesItsTrajectory) {
  const std::string own = (seq() / "mav0/cam0/sensor.yaml").string() + " " + (seq() / "mav0/imu0/sensor.yaml").string();
  for (const std::string tool : {"openvins", "vins"}) {
    SCOPED_TRACE(tool);
    TempDir out;
    std::string log;
    ASSERT_EQ(runAdugs("calib convert " + own + " --to " + tool + " --out " + (out / "calib").string(), &log), 0) << log;
    const std::string files = tool == "vins" ? (out / "calib/config.yaml").string()
                                             : (out / "calib/kalibr_imucam_chain.yaml").string() + " " +
                                                   (out / "calib/kalibr_imu_chain.yaml").string();
    ASSERT_EQ(runAdugs("run -q " + seq().string() + cfg() + " --calibration " + files + " --out " + (out / "run").string(), &log), 0)
        << log;
    EXPECT_LT(maxDifference(out / "run/trajectory.tum"), 1e-6);
    EXPECT_NE(readFile(out / "run/summary.yaml").find(tool == "vins" ? "config.yaml" : "kalibr_imucam_chain.yaml"),
              std::string::npos);
  }
}

TEST_F(CmdRunCalibration, ImuIntrinsicsAreAppliedToTheSamples) {
  // A copy of the sequence whose accelerometer x reads 3 % high (images linked, not copied).
  TempDir copy;
  for (const auto& entry : fs::recursive_directory_iterator(seq())) {
    const fs::path rel = fs::relative(entry.path(), seq()), to = copy / rel.string();
    if (entry.is_directory()) fs::create_directories(to);
    else if (rel != fs::path("mav0/imu0/data.csv")) fs::create_symlink(entry.path(), to);
  }
  std::ifstream in(seq() / "mav0/imu0/data.csv");
  std::ofstream out(copy / "mav0/imu0/data.csv");
  std::string line;
  std::getline(in, line);
  out << line << "\n";
  out.precision(17);
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    ASSERT_EQ(f.size(), 7u);
    out << f[0] << "," << f[1] << "," << f[2] << "," << f[3] << "," << std::stod(f[4]) * 1.03 << "," << f[5] << "," << f[6] << "\n";
  }
  out.close();
  const std::string imu = (seq() / "mav0/imu0/sensor.yaml").string();
  TempDir calib;
  std::string log;
  ASSERT_EQ(runAdugs("calib convert " + (seq() / "mav0/cam0/sensor.yaml").string() + " " + imu +
                         " --to openvins --out " + calib.path().string(),
                     &log),
            0)
      << log;
  // The written IMU file with Ta = diag(1.03, 1, 1) (a_meas = Ta a).
  std::string text = readFile(calib / "kalibr_imu_chain.yaml");
  const size_t ta = text.find("  Ta:\n    - [1, 0, 0]");
  ASSERT_NE(ta, std::string::npos) << text;
  text.replace(ta, std::string("  Ta:\n    - [1, 0, 0]").size(), "  Ta:\n    - [1.03, 0, 0]");
  writeText(calib / "scaled_imu_chain.yaml", text);
  const std::string chain = (calib / "kalibr_imucam_chain.yaml").string();
  TempDir with, without;
  ASSERT_EQ(runAdugs("run -q " + copy.path().string() + cfg() + " --calibration " + chain + " " + (calib / "scaled_imu_chain.yaml").string() +
                         " --out " + with.path().string(),
                     &log),
            0)
      << log;
  ASSERT_EQ(runAdugs("run -q " + copy.path().string() + cfg() + " --calibration " + chain + " " + (calib / "kalibr_imu_chain.yaml").string() +
                         " --out " + without.path().string(),
                     &log),
            0)
      << log;
  const double corrected = maxDifference(with / "trajectory.tum");
  const double uncorrected = maxDifference(without / "trajectory.tum");
  std::cout << "largest difference to the original run: with Ta " << corrected << " m, without " << uncorrected << " m\n";
  EXPECT_LT(corrected, 1e-6);  // the corrected samples equal the original ones to the CSV's digits
  EXPECT_GT(uncorrected, 100 * std::max(corrected, 1e-6));
}

}  // namespace
}  // namespace adugs

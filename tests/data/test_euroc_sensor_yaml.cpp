// EuRoC sensor.yaml: the real files, write -> read round trips, and every kind of bad input.
#include <optional>

#include <gtest/gtest.h>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

const char* kCameraYaml =
    "%YAML:1.0\n"
    "sensor_type: camera\n"
    "comment: test cam\n"
    "T_BS:\n"
    "  cols: 4\n"
    "  rows: 4\n"
    "  data: [0.0, -1.0, 0.0, 0.1,\n"
    "         1.0, 0.0, 0.0, 0.2,\n"
    "         0.0, 0.0, 1.0, 0.3,\n"
    "         0.0, 0.0, 0.0, 1.0]\n"
    "rate_hz: 20\n"
    "resolution: [752, 480]\n"
    "camera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
    "distortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28, 0.07, 0.0002, 1.7e-05]\n";

const char* kImuYaml =
    "%YAML:1.0\n"
    "sensor_type: imu\n"
    "rate_hz: 200\n"
    "gyroscope_noise_density: 1.6968e-04\n"
    "gyroscope_random_walk: 1.9393e-05\n"
    "accelerometer_noise_density: 2.0000e-3\n"
    "accelerometer_random_walk: 3.0000e-3\n";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  size_t pos = text.find(from);
  if (pos == std::string::npos) throw std::logic_error("test bug: '" + from + "' not in text");
  return text.replace(pos, from.size(), to);
}

std::optional<InputError> cameraError(const std::string& text) {
  try {
    parseEurocCameraYaml(text, "cam0/sensor.yaml");
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

void expectCameraError(const std::string& text, long line, const std::string& field, const std::string& words) {
  auto err = cameraError(text);
  ASSERT_TRUE(err) << "accepted:\n" << text;
  EXPECT_EQ(err->file(), "cam0/sensor.yaml");
  EXPECT_EQ(err->line(), line) << err->what();
  EXPECT_EQ(err->field(), field) << err->what();
  EXPECT_NE(std::string(err->what()).find(words), std::string::npos) << err->what();
}

TEST(EurocSensorYaml, ParsesCameraText) {
  CameraCalibration c = parseEurocCameraYaml(kCameraYaml, "cam.yaml");
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.fx, 458.654);
  EXPECT_DOUBLE_EQ(c.cy, 248.375);
  EXPECT_EQ(c.distortion_model, DistortionModel::kRadialTangential);
  ASSERT_EQ(c.distortion.size(), 4u);
  EXPECT_DOUBLE_EQ(c.distortion[3], 1.7e-05);
  EXPECT_DOUBLE_EQ(c.rate_hz, 20.0);
  // T_BS maps camera points into the body frame: the camera x axis is body y.
  Eigen::Vector3d p_B = c.T_B_C * Eigen::Vector3d(1, 0, 0);
  EXPECT_TRUE(p_B.isApprox(Eigen::Vector3d(0.1, 1.2, 0.3), 1e-12)) << p_B.transpose();
}

TEST(EurocSensorYaml, ReadsRealEurocFiles) {
  fs::path mav = adugs::test::sharedDataDir() / "euroc_v101_micro" / "mav0";
  ADUGS_REQUIRE_SHARED(mav);
  CameraCalibration c = readEurocCameraYaml((mav / "cam0" / "sensor.yaml").string());
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.fx, 458.654);
  EXPECT_DOUBLE_EQ(c.fy, 457.296);
  EXPECT_DOUBLE_EQ(c.cx, 367.215);
  EXPECT_DOUBLE_EQ(c.cy, 248.375);
  EXPECT_EQ(c.distortion_model, DistortionModel::kRadialTangential);
  EXPECT_DOUBLE_EQ(c.distortion[0], -0.28340811);
  EXPECT_NEAR(c.T_B_C.translation().x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(c.T_B_C.linear()(1, 0), 0.999557249008, 1e-9);
  EXPECT_NEAR(c.T_B_C.linear().determinant(), 1.0, 1e-12);

  ImuNoise imu = readEurocImuYaml((mav / "imu0" / "sensor.yaml").string());
  EXPECT_DOUBLE_EQ(imu.rate_hz, 200);
  EXPECT_DOUBLE_EQ(imu.gyro_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(imu.gyro_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(imu.accel_noise_density, 2.0e-3);
  EXPECT_DOUBLE_EQ(imu.accel_random_walk, 3.0e-3);
  EXPECT_TRUE(imu.T_B_I.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(EurocSensorYaml, CameraRoundTripsExactly) {
  CameraCalibration c;
  c.width = 640;
  c.height = 400;
  c.fx = 400.123456789012;
  c.fy = 401.5;
  c.cx = 319.9;
  c.cy = 0.1 + 0.2;  // not exactly representable in short decimal form
  c.distortion_model = DistortionModel::kEquidistant;
  c.distortion = {0.1, -0.01, 1e-7, 3.3333333333333335e-05};
  c.rate_hz = 30;
  c.T_B_C = Eigen::Translation3d(0.01, -0.02, 0.03) *
            Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized());
  adugs::test::TempDir dir;
  std::string path = (dir / "sensor.yaml").string();
  writeEurocCameraYaml(path, c);
  CameraCalibration r = readEurocCameraYaml(path);
  EXPECT_EQ(r.width, c.width);
  EXPECT_EQ(r.height, c.height);
  EXPECT_EQ(r.fx, c.fx);
  EXPECT_EQ(r.cy, c.cy);
  EXPECT_EQ(r.distortion_model, c.distortion_model);
  EXPECT_EQ(r.distortion, c.distortion);
  EXPECT_EQ(r.rate_hz, c.rate_hz);
  EXPECT_TRUE(r.T_B_C.matrix().isApprox(c.T_B_C.matrix(), 1e-14)) << r.T_B_C.matrix();
}

TEST(EurocSensorYaml, ImuRoundTripsExactly) {
  ImuNoise n;
  n.rate_hz = 400;
  n.gyro_noise_density = 1.6968e-04;
  n.gyro_random_walk = 1.0 / 3.0;
  n.accel_noise_density = 2e-3;
  n.accel_random_walk = 3e-3;
  n.T_B_I = Eigen::Translation3d(0, 0, 0.05) * Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ());
  adugs::test::TempDir dir;
  std::string path = (dir / "imu.yaml").string();
  writeEurocImuYaml(path, n);
  ImuNoise r = readEurocImuYaml(path);
  EXPECT_EQ(r.rate_hz, n.rate_hz);
  EXPECT_EQ(r.gyro_noise_density, n.gyro_noise_density);
  EXPECT_EQ(r.gyro_random_walk, n.gyro_random_walk);
  EXPECT_EQ(r.accel_noise_density, n.accel_noise_density);
  EXPECT_EQ(r.accel_random_walk, n.accel_random_walk);
  EXPECT_TRUE(r.T_B_I.matrix().isApprox(n.T_B_I.matrix(), 1e-14));
}

TEST(EurocSensorYaml, MissingKeyIsNamed) {
  expectCameraError(replaced(kCameraYaml, "intrinsics: [458.654, 457.296, 367.215, 248.375]\n", ""), 2,
                    "intrinsics", "missing required key");
  expectCameraError(replaced(kCameraYaml, "  rows: 4\n", ""), 5, "T_BS.rows", "missing required key");
}

TEST(EurocSensorYaml, WrongTypeIsNamed) {
  expectCameraError(replaced(kCameraYaml, "[752, 480]", "[752, wide]"), 12, "resolution[1]", "expected an integer");
  expectCameraError(replaced(kCameraYaml, "rate_hz: 20", "rate_hz: fast"), 11, "rate_hz", "expected a number");
  expectCameraError(replaced(kCameraYaml, "camera_model: pinhole", "camera_model: [pinhole]"), 13, "camera_model",
                    "found a list");
  expectCameraError(replaced(kCameraYaml, "  cols: 4\n", "  cols: 4.5\n"), 5, "T_BS.cols", "expected an integer");
}

TEST(EurocSensorYaml, NonFiniteIsNamed) {
  expectCameraError(replaced(kCameraYaml, "458.654,", ".nan,"), 14, "intrinsics[0]", "not finite");
  expectCameraError(replaced(kCameraYaml, "0.0, 0.0, 1.0, 0.3,", "0.0, 0.0, .inf, 0.3,"), 9, "T_BS.data[10]",
                    "not finite");
}

TEST(EurocSensorYaml, WrongCountIsNamed) {
  expectCameraError(replaced(kCameraYaml, "[458.654, 457.296, 367.215, 248.375]", "[458.654, 457.296, 367.215]"),
                    14, "intrinsics", "found 3 numbers");
  expectCameraError(replaced(kCameraYaml, "1.7e-05]", "1.7e-05, 0.1]"), 16, "distortion_coefficients",
                    "expected 4 coefficients, found 5");
  expectCameraError(replaced(kCameraYaml, "[752, 480]", "[752]"), 12, "resolution", "expected [width, height]");
  expectCameraError(replaced(kCameraYaml, "         0.0, 0.0, 0.0, 1.0]", "         0.0, 0.0, 0.0]"), 7,
                    "T_BS.data", "expected 16 numbers");
  expectCameraError(replaced(kCameraYaml, "  rows: 4", "  rows: 3"), 6, "T_BS.rows", "expected 4, found 3");
}

TEST(EurocSensorYaml, NonRigidTransformIsRejected) {
  // A scaled rotation.
  expectCameraError(replaced(kCameraYaml, "0.0, 0.0, 1.0, 0.3,", "0.0, 0.0, 1.1, 0.3,"), 7, "T_BS.data",
                    "not a rigid transform");
  // A reflection (det -1).
  expectCameraError(replaced(kCameraYaml, "0.0, 0.0, 1.0, 0.3,", "0.0, 0.0, -1.0, 0.3,"), 7, "T_BS.data",
                    "det R = -1");
  // A bad last row.
  expectCameraError(replaced(kCameraYaml, "0.0, 0.0, 0.0, 1.0]", "0.0, 0.0, 0.5, 1.0]"), 7, "T_BS.data",
                    "last row");
  // Rounding noise far below the tolerance is accepted and re-orthonormalised.
  CameraCalibration c = parseEurocCameraYaml(replaced(kCameraYaml, "0.0, 0.0, 1.0, 0.3,", "0.0, 0.0, 1.000000001, 0.3,"), "x");
  EXPECT_NEAR((c.T_B_C.linear().transpose() * c.T_B_C.linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-14);
}

TEST(EurocSensorYaml, BadValuesAndUnknownKeysAreRejected) {
  expectCameraError(replaced(kCameraYaml, "458.654,", "-458.654,"), 14, "intrinsics", "must be positive");
  expectCameraError(replaced(kCameraYaml, "[752, 480]", "[0, 480]"), 12, "resolution", "must be positive");
  expectCameraError(replaced(kCameraYaml, "rate_hz: 20", "rate_hz: 0"), 11, "rate_hz", "must be positive");
  expectCameraError(replaced(kCameraYaml, "camera_model: pinhole", "camera_model: kb8"), 13, "camera_model",
                    "expected 'pinhole', 'omni', 'ds' or 'eucm', found 'kb8'");
  expectCameraError(replaced(kCameraYaml, "radial-tangential", "fov"), 15, "distortion_model", "found 'fov'");
  expectCameraError(replaced(kCameraYaml, "sensor_type: camera", "sensor_type: imu"), 2, "sensor_type",
                    "expected 'camera'");
  expectCameraError(std::string(kCameraYaml) + "focal_length: 3\n", 17, "focal_length", "unknown key");
  expectCameraError(replaced(kCameraYaml, "  rows: 4\n", "  rows: 4\n  order: row-major\n"), 7, "T_BS.order",
                    "unknown key");
}

TEST(EurocSensorYaml, ImuErrorsAreNamed) {
  auto imuError = [](const std::string& text) -> std::optional<InputError> {
    try {
      parseEurocImuYaml(text, "imu0/sensor.yaml");
    } catch (const InputError& e) {
      return e;
    }
    return std::nullopt;
  };
  ImuNoise ok = parseEurocImuYaml(kImuYaml, "imu0/sensor.yaml");
  EXPECT_DOUBLE_EQ(ok.accel_random_walk, 3e-3);

  auto err = imuError(replaced(kImuYaml, "gyroscope_random_walk: 1.9393e-05\n", ""));
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "gyroscope_random_walk");
  err = imuError(replaced(kImuYaml, "2.0000e-3", "-2.0e-3"));
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "accelerometer_noise_density");
  EXPECT_EQ(err->line(), 6);
  err = imuError(replaced(kImuYaml, "3.0000e-3", "inf"));
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("not finite"), std::string::npos);
  err = imuError(replaced(kImuYaml, "sensor_type: imu", "sensor_type: camera"));
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "sensor_type");
  err = imuError(std::string(kImuYaml) + "intrinsics: [1, 2, 3, 4]\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "intrinsics");
  EXPECT_EQ(err->line(), 8);
}

TEST(EurocSensorYaml, FileErrorsNameThePath) {
  adugs::test::TempDir dir;
  std::string path = (dir / "sensor.yaml").string();
  try {
    readEurocCameraYaml(path);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
  }
  adugs::test::writeText(path, "%YAML:1.0\nsensor_type: camera\nT_BS: [1, 2\n");
  try {
    readEurocCameraYaml(path);
    FAIL() << "no error for a syntax error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_GE(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("syntax"), std::string::npos);
  }
  EXPECT_THROW(writeEurocImuYaml((dir / "no" / "such" / "dir.yaml").string(), ImuNoise()), InputError);
}

}  // namespace
}  // namespace adugs::data

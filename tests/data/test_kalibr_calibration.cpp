// Kalibr camchain-imucam.yaml / imu.yaml reading: the built-in dataset presets, the frame
// conversion T_B_C = T_cam_imu^-1, and errors naming file and key.
#include <gtest/gtest.h>

#include "data/formats/kalibr_calibration.h"
#include "data/input_error.h"
#include "data/sources/dataset_preset.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

TEST(KalibrCalibration, EveryPresetParses) {
  for (const char* preset : {"euroc", "tum-vi", "viode", "openloris"}) {
    SCOPED_TRACE(preset);
    const std::string cam = presetCalibrationText(preset, "camchain-imucam.yaml");
    const std::string imu = presetCalibrationText(preset, "imu.yaml");
    ASSERT_FALSE(cam.empty());
    ASSERT_FALSE(imu.empty());
    const RigCamera c = parseKalibrCamchain(cam, preset);
    EXPECT_TRUE(c.has_T_imu_cam);
    EXPECT_GT(c.camera.width, 0);
    EXPECT_FALSE(c.rostopic.empty());
    const RigImu i = parseKalibrImu(imu, preset);
    EXPECT_GT(i.noise.gyro_noise_density, 0);
  }
  EXPECT_EQ(parseKalibrCamchain(presetCalibrationText("tum-vi", "camchain-imucam.yaml"), "tum-vi")
                .camera.distortion_model,
            DistortionModel::kEquidistant);
}

TEST(KalibrCalibration, EurocPresetIsTheSensorYamlExtrinsicInverted) {
  const auto sensor = test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/sensor.yaml";
  ADUGS_REQUIRE_SHARED(sensor);
  const CameraCalibration euroc = readEurocCameraYaml(sensor.string());
  const RigCamera k = parseKalibrCamchain(presetCalibrationText("euroc", "camchain-imucam.yaml"), "euroc");
  EXPECT_LT((k.camera.T_B_C.matrix() - euroc.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_DOUBLE_EQ(k.camera.fx, euroc.fx);
  EXPECT_EQ(k.camera.distortion, euroc.distortion);
}

TEST(KalibrCalibration, HandWrittenFileWithTimeShift) {
  // T_cam_imu: rotation of +90 deg about z, translation (1, 0, 0). Its inverse T_B_C maps the
  // camera origin to R^T * -(1, 0, 0) = (0, 1, 0).
  const std::string text =
      "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 401, 320, 240]\n  distortion_model: radtan\n"
      "  distortion_coeffs: [0.1, -0.01, 0.001, 0.0001]\n  resolution: [640, 480]\n"
      "  T_cam_imu:\n  - [0, -1, 0, 1]\n  - [1, 0, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
      "  timeshift_cam_imu: -0.0025\n  rostopic: /cam0/image_raw\n  cam_overlaps: []\n";
  const RigCamera k = parseKalibrCamchain(text, "chain.yaml");
  EXPECT_EQ(k.time_offset_s, -0.0025);
  EXPECT_TRUE(k.camera.T_B_C.translation().isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_EQ(k.camera.width, 640);
  EXPECT_EQ(k.camera.height, 480);
  EXPECT_EQ(k.camera.fx, 400);
  EXPECT_EQ(k.camera.fy, 401);
  EXPECT_EQ(k.camera.cx, 320);
  EXPECT_EQ(k.camera.cy, 240);
  EXPECT_EQ(k.camera.distortion_model, DistortionModel::kRadialTangential);
  EXPECT_EQ(k.camera.distortion, (std::vector<double>{0.1, -0.01, 0.001, 0.0001}));
  // The rotation too: R_B_C = R_cam_imu^T, so the camera's x axis is the body's -y.
  EXPECT_TRUE(k.camera.T_B_C.rotation().col(0).isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_EQ(k.rostopic, "/cam0/image_raw");
}

TEST(KalibrCalibration, ErrorsNameFileLineAndKey) {
  auto error = [](const std::string& text) {
    try {
      parseKalibrCamchain(text, "chain.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string base =
      "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 401, 320, 240]\n  distortion_model: radtan\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  EXPECT_NE(error(base + "  T_cam_imu: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]\n")
                .find("T_cam_imu"),
            std::string::npos);
  const std::string fov = error(
      "cam0:\n  camera_model: fov\n  intrinsics: [1, 400, 401, 320, 240]\n  distortion_model: radtan\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n");
  EXPECT_NE(fov.find("chain.yaml:2"), std::string::npos) << fov;
  EXPECT_NE(fov.find("'fov'"), std::string::npos) << fov;
  EXPECT_NE(error(base + "  distortion_model: fov\n").find("distortion_model"), std::string::npos);
  EXPECT_NE(error("cam1:\n  camera_model: pinhole\n").find("cam0"), std::string::npos);
  try {
    parseKalibrImu("imu0:\n  accelerometer_noise_density: 0.01\n", "imu.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("accelerometer_random_walk"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adugs::data

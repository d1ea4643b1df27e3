// Camera-IMU files: camchain-imucam.yaml and imu.yaml read back, the yac config, the report.
#include <gtest/gtest.h>

#include <cmath>

#include "calib/camera_imu/camera_imu_input.h"
#include "calib/camera_imu/camera_imu_report.h"
#include "data/input_error.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(CameraImuIo, CamchainImuCamAndImuYamlReadBack) {
  test::TempDir tmp("adugs_cimu_io");
  const CalibCamera cam = synth::eurocLikeCamera();
  CameraImuResult r;
  r.T_C_I.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  r.T_C_I.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  r.time_shift_s = -0.0042;
  const std::string yaml = formatCamchainImuCamYaml(cam, r);
  EXPECT_NE(yaml.find("timeshift_cam_imu: -0.0042\n"), std::string::npos) << yaml;
  test::writeText(tmp / "camchain-imucam.yaml", yaml);
  const CalibCamera back = readKalibrCamchain((tmp / "camchain-imucam.yaml").string());
  EXPECT_EQ(back.width, 752);
  EXPECT_EQ(back.model, cam.model);
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(back.params[i], cam.params[i]);

  ImuNoiseFigures f{0.002, 0.003, 1.6968e-04, 1.9393e-05, 200};
  test::writeText(tmp / "imu.yaml", formatImuYaml(f));
  const ImuNoiseFigures g = readKalibrImuYaml((tmp / "imu.yaml").string());
  EXPECT_DOUBLE_EQ(g.gyro_noise_density, f.gyro_noise_density);
  EXPECT_DOUBLE_EQ(g.accel_random_walk, f.accel_random_walk);
  EXPECT_DOUBLE_EQ(g.update_rate_hz, 200);
}

TEST(CameraImuIo, YacConfigErrorsNameTheKey) {
  test::TempDir tmp("adugs_cimu_io");
  test::writeText(tmp / "c.yaml",
                  "cam0:\n  resolution: [752, 480]\n  proj_model: pinhole\n  dist_model: banana\n"
                  "  proj_params: [1, 1, 1, 1]\n  dist_params: [0, 0, 0, 0]\n");
  try {
    readYacCalibConfig((tmp / "c.yaml").string());
    FAIL() << "expected an InputError";
  } catch (const data::InputError& e) {
    EXPECT_EQ(e.field(), "cam0.dist_model");
    EXPECT_EQ(e.line(), 4);
  }
}

TEST(CameraImuIo, CompareTransformsHandValues) {
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
  b.linear() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  b.translation() = Eigen::Vector3d(0.003, 0.004, 0);
  double angle = 0, dist = 0;
  compareTransforms(a, b, angle, dist);
  EXPECT_NEAR(angle, 1.0, 1e-9);
  EXPECT_NEAR(dist, 0.005, 1e-12);
}

}  // namespace
}  // namespace adugs::calib

// Camera-IMU calibration end to end: synthetic recording with known truth, and the real EuRoC
// imu_april detections + IMU against EuRoC's published cam0 T_BS.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "calib/camera_imu/camera_imu_calibrator.h"
#include "calib/camera_imu/camera_imu_input.h"
#include "calib/camera_imu/camera_imu_report.h"
#include "calib/camera_imu/camera_imu_verdict.h"
#include "calib/target/corner_csv.h"
#include "data/input_error.h"
#include "tests/calib/camera_imu_synthetic.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  double angle = 0, dist = 0;
  compareTransforms(a, b, angle, dist);
  return angle;
}

TEST(CameraImuCalibrator, SyntheticRecoversExtrinsicsAndFiveMsOffset) {
  const synth::CameraImuRecording rec = synth::makeCameraImuRecording(16.0, 0.005);
  CameraImuOptions o;
  o.gravity = data::kSimGravity;
  const CameraImuResult r = calibrateCameraImu(rec.views, rec.camera, rec.imu, rec.noise, o);
  EXPECT_NEAR(r.time_shift_s, 0.005, 0.0005);
  EXPECT_LT(rotationErrorDeg(r.T_C_I, rec.T_C_I), 0.1);
  EXPECT_LT((r.T_C_I.inverse().translation() - rec.T_C_I.inverse().translation()).norm(), 0.002);
  EXPECT_LT((r.gyro_bias - rec.gyro_bias).norm(), 0.002);
  EXPECT_LT((r.accel_bias - rec.accel_bias).norm(), 0.05);
  // The sim's gravity is -z of its world = the target frame.
  EXPECT_LT((r.gravity_T - Eigen::Vector3d(0, 0, -data::kSimGravity)).norm(), 0.02);
  EXPECT_LT(r.reprojection_rms_px, 0.6);  // 0.3 px noise per axis
  EXPECT_GT(r.frames_used, 250);
  // The formal 1-sigma is of the size of the errors on these data (noise only, right model).
  ASSERT_TRUE(r.has_sigma);
  EXPECT_LT(r.sigma_rotation.maxCoeff() * 180 / M_PI, 0.05);
  EXPECT_LT(r.sigma_translation.maxCoeff(), 0.002);
  EXPECT_EQ(judgeCameraImu(r, o).verdict, Verdict::kOk) << formatVerdict(judgeCameraImu(r, o), "");
}

TEST(CameraImuCalibrator, FixedTimeOffsetStaysZero) {
  const synth::CameraImuRecording rec = synth::makeCameraImuRecording(8.0, 0.0);
  CameraImuOptions o;
  o.gravity = data::kSimGravity;
  o.estimate_time_offset = false;
  const CameraImuResult r = calibrateCameraImu(rec.views, rec.camera, rec.imu, rec.noise, o);
  EXPECT_EQ(r.time_shift_s, 0.0);
  EXPECT_LT(rotationErrorDeg(r.T_C_I, rec.T_C_I), 0.1);
}

TEST(CameraImuCalibrator, NoRotationIsNotSolved) {
  synth::CameraImuRecording rec = synth::makeCameraImuRecording(4.0, 0.0);
  for (auto& g : rec.imu.gyro) g *= 0.01;  // the gyro says: no rotation
  const CameraImuOptions o;
  const CameraImuResult r = calibrateCameraImu(rec.views, rec.camera, rec.imu, rec.noise, o);
  EXPECT_FALSE(r.solved);
  EXPECT_LT(r.excitation(0), o.min_rotation_rate);
  EXPECT_EQ(judgeCameraImu(r, o).verdict, Verdict::kFailed);
}

// EuRoC imu_april: cam0 detections (1,439 frames at 20 Hz) + IMU; every 2nd frame.
TEST(CameraImuCalibrator, EurocImuAprilMatchesPublishedExtrinsics) {
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "imu_april";
  const auto reference =
      test::sharedDataDir() / "euroc_v101_micro" / "mav0" / "cam0" / "sensor.yaml";
  ADUGS_REQUIRE_SHARED(dir);
  ADUGS_REQUIRE_SHARED(reference);
  const CameraImuSensors sensors = readYacCalibConfig((dir / "config.yaml").string());
  const auto views = readCornerCsvs((dir / "cam0").string(), nullptr);
  const ImuRecording imu = readImuCsv((dir / "imu0.csv").string());
  CameraImuOptions o;
  o.frame_step = 2;
  o.gravity = sensors.gravity;
  const CameraImuResult r = calibrateCameraImu(views, sensors.camera, imu, sensors.imu, o);
  const Eigen::Isometry3d T_I_C_ref = readEurocCameraToImu(reference.string());
  EXPECT_LT(rotationErrorDeg(r.T_C_I, T_I_C_ref.inverse()), 0.5);
  EXPECT_LT((r.T_C_I.inverse().translation() - T_I_C_ref.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(r.time_shift_s), 0.001);
  EXPECT_LT(r.reprojection_rms_px, 1.0);
  EXPECT_EQ(judgeCameraImu(r, o).verdict, Verdict::kOk) << formatVerdict(judgeCameraImu(r, o), "");
}

}  // namespace
}  // namespace adugs::calib

// Initial guess of the camera-IMU calibration: Kabsch rotation and the rate cross-correlation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "calib/camera_imu/camera_imu_init.h"

namespace adugs::calib {
namespace {

Eigen::Vector3d rateAt(double t) {
  return {0.8 * std::sin(1.7 * t) + 0.3 * std::sin(5.1 * t), 0.6 * std::cos(2.3 * t + 0.4),
          0.5 * std::sin(3.1 * t + 1.0) + 0.2 * std::cos(0.7 * t)};
}

TEST(CameraImuInit, AlignVectorsRecoversRotation) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 50; ++i) {
    b.push_back(rateAt(0.1 * i));
    a.push_back(R * b.back());
  }
  EXPECT_LT((alignVectors(a, b) - R).norm(), 1e-12);
}

// Gyro in the IMU frame at 200 Hz; camera rates (frame pairs at 20 Hz, camera clock) are the
// same motion seen R_C_I-rotated, with t_imu = t_cam + shift.
TEST(CameraImuInit, TimeOffsetAndRotationFromSyntheticRates) {
  const double shift = 0.035;
  const Eigen::Matrix3d R_C_I =
      Eigen::AngleAxisd(1.2, Eigen::Vector3d(1, 1, -0.5).normalized()).toRotationMatrix();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.01);
  std::vector<RateSample> imu;
  for (int k = 0; k < 200 * 20; ++k) {
    const double t = k * 0.005;
    imu.push_back({t, rateAt(t) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))});
  }
  std::vector<RateSample> cam;
  for (int k = 2; k < 20 * 19; ++k) {
    const double t = k * 0.05 + 0.025;  // pair midpoint, camera clock
    // Mean rate over the pair: integrate the true rate numerically.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int i = 0; i < 100; ++i) mean += rateAt(t + shift - 0.025 + (i + 0.5) * 0.0005) / 100;
    cam.push_back({t, R_C_I * mean});
  }
  const double found = timeOffsetByCorrelation(cam, imu, 0.05, 0.2);
  EXPECT_NEAR(found, shift, 0.0051);  // the IMU period
  double rms = 0;
  const Eigen::Matrix3d R = rotationFromAngularRates(cam, imu, 0.05, found, &rms);
  const double angle = Eigen::AngleAxisd(R.transpose() * R_C_I).angle();
  EXPECT_LT(angle * 180 / M_PI, 0.5);
  EXPECT_LT(rms, 0.02);
}

TEST(CameraImuInit, ExcitationSeesSingleAxisMotion) {
  std::vector<RateSample> imu;
  for (int k = 0; k < 1000; ++k)
    imu.push_back({k * 0.005, Eigen::Vector3d(0, 0, std::sin(k * 0.01))});
  const Eigen::Vector3d e = rotationExcitation(imu);
  EXPECT_GT(e(0), 0.5);
  EXPECT_LT(e(1), 1e-9);
  EXPECT_LT(e(2), 1e-9);
}

}  // namespace
}  // namespace adugs::calib

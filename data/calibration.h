#pragma once
// The calibration a sequence comes with, whatever file it was read from (EuRoC sensor.yaml,
// Kalibr, a dataset preset, a live camera's defaults): the camera (intrinsics, distortion,
// camera -> body transform, rate) and the IMU's noise.
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace adugs::data {

enum class DistortionModel { kRadialTangential, kEquidistant };

// "radial-tangential" / "equidistant" (the EuRoC spellings).
std::string toString(DistortionModel model);

struct CameraCalibration {
  int width = 0;  // pixels
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  DistortionModel distortion_model = DistortionModel::kRadialTangential;
  std::vector<double> distortion;  // 4 coefficients, see above
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();  // camera -> body (EuRoC T_BS)
  double rate_hz = 0;
};

struct ImuNoise {
  double gyro_noise_density = 0;   // rad / s / sqrt(Hz)
  double gyro_random_walk = 0;     // rad / s^2 / sqrt(Hz)
  double accel_noise_density = 0;  // m / s^2 / sqrt(Hz)
  double accel_random_walk = 0;    // m / s^3 / sqrt(Hz)
  double rate_hz = 0;
  Eigen::Isometry3d T_B_I = Eigen::Isometry3d::Identity();  // IMU -> body (T_BS; optional key)
};

}  // namespace adugs::data

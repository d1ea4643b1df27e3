#pragma once
// Kalibr output files: camchain.yaml (one camera) and imu.yaml (noise figures).
#include <string>

#include "calib/calib_camera.h"

namespace adugs::calib {

// cam0:
//   camera_model: pinhole | omni | ds | eucm
//   intrinsics: [fu, fv, pu, pv], omni [xi, fu, fv, pu, pv], ds [xi, alpha, fu, fv, pu, pv],
//               eucm [alpha, beta, fu, fv, pu, pv]
//   distortion_model: radtan | equidistant | none
//   distortion_coeffs: [..4..] ([] for none)
//   resolution: [w, h]
//   ...
std::string formatCamchainYaml(const CalibCamera& camera, const std::string& camera_name = "cam0",
                               const std::string& rostopic = "/cam0/image_raw");

struct ImuNoiseFigures {
  double accel_noise_density = 0;  // m/s^2/sqrt(Hz)
  double accel_random_walk = 0;    // m/s^3/sqrt(Hz)
  double gyro_noise_density = 0;   // rad/s/sqrt(Hz)
  double gyro_random_walk = 0;     // rad/s^2/sqrt(Hz)
  double update_rate_hz = 0;
};
std::string formatImuYaml(const ImuNoiseFigures& imu, const std::string& rostopic = "/imu0");

}  // namespace adugs::calib

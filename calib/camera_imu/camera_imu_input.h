#pragma once
// Inputs of the camera-IMU calibration besides the detections and the IMU samples: the camera
// intrinsics and the IMU noise figures, from the files users have at hand:
//   - a yac/EuRoC calibration config.yaml (cam0: proj_params, dist_params, dist_model, resolution;
//     imu0: rate, sigma_a_c, sigma_g_c, sigma_aw_c, sigma_gw_c, g),
//   - a Kalibr camchain.yaml (cam0: intrinsics, distortion_coeffs, distortion_model, resolution)
//     plus a Kalibr imu.yaml,
//   - an EuRoC cam0/sensor.yaml (reference T_BS to compare with).
// These are foreign formats with many keys we do not use, so only the keys read are checked;
// missing or malformed ones are InputError naming the file, line and key.
#include <Eigen/Geometry>
#include <string>

#include "calib/kalibr_yaml.h"
#include "calib/calib_camera.h"

namespace adugs::calib {

struct CameraImuSensors {
  CalibCamera camera;
  bool has_camera = false;
  ImuNoiseFigures imu;
  bool has_imu = false;
  double gravity = 9.81;  // m/s^2 (config.yaml imu0.g when given)
};

// config.yaml (yac): camera `camera_name` and imu0.
CameraImuSensors readYacCalibConfig(const std::string& path,
                                    const std::string& camera_name = "cam0");
// Kalibr camchain.yaml (or camchain-imucam.yaml): the camera block.
CalibCamera readKalibrCamchain(const std::string& path, const std::string& camera_name = "cam0");
// Kalibr imu.yaml: the four noise figures and update_rate.
ImuNoiseFigures readKalibrImuYaml(const std::string& path);
// EuRoC cam0/sensor.yaml: T_BS as T_I_C (camera -> IMU/body).
Eigen::Isometry3d readEurocCameraToImu(const std::string& path);

}  // namespace adugs::calib

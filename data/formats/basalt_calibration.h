#pragma once
// Basalt's calibration JSON (cereal): {"value0": {T_imu_cam: [{px py pz qx qy qz qw}, ...]
// (camera -> IMU), intrinsics: [{camera_type: pinhole | kb4 | ds | eucm | unified, intrinsics:
// {fx fy cx cy [k1..k4 | xi alpha | alpha beta | alpha]}}], resolution: [[w, h], ...],
// imu_update_rate, accel_noise_std, gyro_noise_std, accel_bias_std, gyro_bias_std (densities,
// per axis), cam_time_offset_ns, calib_accel_bias, calib_gyro_bias, vignette, ...}}.
// Basalt's "unified" camera is EUCM with beta = 1. Per-axis noise figures that differ are taken
// at their largest. The scale/misalignment entries of calib_accel_bias / calib_gyro_bias become
// the IMU intrinsics (applied to the samples); their static biases are listed as ignored (the
// estimator estimates its own).
#include <string>

#include "data/calibration.h"

namespace adugs::data {

class YamlOptionsReader;

// True for a map whose top key is cereal's "value0" with Basalt's T_imu_cam in it.
bool isBasaltFile(const YamlOptionsReader& root);
void readBasaltFile(YamlOptionsReader root, RigCalibration& rig);

}  // namespace adugs::data

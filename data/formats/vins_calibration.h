#pragma once
// VINS-Mono and VINS-Fusion configurations (OpenCV FileStorage YAML, "%YAML:1.0"):
//   VINS-Fusion  imu, num_of_cam, cam0_calib / cam1_calib (camera files named relative to the
//                config), body_T_cam0 / body_T_cam1 (!!opencv-matrix 4x4, camera -> IMU),
//                acc_n, gyr_n, acc_w, gyr_w, td, imu_topic, image0_topic, ...
//   VINS-Mono    the camera keys in the config itself, extrinsicRotation (imu^R_cam) and
//                extrinsicTranslation (!!opencv-matrix), the same noise keys and td
//   camera file  model_type PINHOLE (distortion_parameters k1 k2 p1 p2, projection_parameters
//                fx fy cx cy) | MEI (mirror_parameters xi, the same distortion, projection
//                gamma1 gamma2 u0 v0) | KANNALA_BRANDT (projection_parameters k2 k3 k4 k5 mu mv
//                u0 v0: camodocal's names for Kalibr's equidistant k1..k4 fu fv pu pv),
//                image_width, image_height
// The noise values are per-sample standard deviations (RigImu::noise_per_sample); td follows
// Kalibr's sign (t_imu = t_cam + td).
#include "data/calibration.h"

namespace adugs::data {

class YamlOptionsReader;

// True for a map with VINS' keys (model_type, cam0_calib, body_T_cam0, acc_n, extrinsicRotation).
bool isVinsFile(const YamlOptionsReader& root);
// A config (with the camera files it names) or a lone camera file, added to rig.
void readVinsFile(YamlOptionsReader root, const std::string& path, RigCalibration& rig);

}  // namespace adugs::data

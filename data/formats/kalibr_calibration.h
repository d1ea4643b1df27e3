#pragma once
// Kalibr's calibration files, and OpenVINS' variants of them (its config/*/kalibr_*.yaml):
//   camchain(-imucam).yaml  cam0, cam1, ...: camera_model pinhole | omni | ds | eucm,
//                           intrinsics ([xi] [alpha beta] fu fv pu pv, Kalibr's order),
//                           distortion_model radtan | equidistant | none, distortion_coeffs,
//                           resolution, T_cam_imu (IMU -> camera; OpenVINS may write T_imu_cam,
//                           camera -> IMU, instead), T_cn_cnm1, timeshift_cam_imu, rostopic
//   imu.yaml                the noise figures, flat (Kalibr's documented input form) or under
//                           imu0: (its results), with T_i_b, update_rate, rostopic, and the
//                           scale-misalignment blocks of its results (gyroscopes: M, A,
//                           C_gyro_i; accelerometers: M) or OpenVINS' Tw, Tg, R_IMUtoGYRO, Ta,
//                           R_IMUtoACC with model: kalibr | rpng | calibrated
// Converted at this boundary to the project's frames: T_B_C = T_cam_imu^-1 (body = IMU).
// The *Map readers read every key they know from one map and leave the rest: the project's own
// files (d435i.yaml's cam0:/imu0:) then call finish(), so a typo is an error; another tool's file
// lists the rest as ignored.
#include <string>
#include <vector>

#include "data/calibration.h"

namespace adugs::data {

class YamlOptionsReader;

// One camera's map (the keys under "cam0:"). A missing or wrong value, a camera or distortion
// model the project cannot use, or a transform that is not rigid is an InputError naming the key.
RigCamera readKalibrCameraMap(YamlOptionsReader& camera);
// The IMU's map (the keys under "imu0:", or a flat file's top level). The unknown keys of its
// gyroscopes:/accelerometers: blocks are errors, or appended to nested_unused when given.
RigImu readKalibrImuMap(YamlOptionsReader& imu, std::vector<std::string>* nested_unused = nullptr);

// Whole files, as Kalibr and OpenVINS write them: every camera of a camchain (cam0, cam1, ...,
// in order), the IMU of an imu file, added to rig (keys that do not change the estimate go to
// rig.ignored_keys).
void readKalibrCamchain(YamlOptionsReader root, RigCalibration& rig);
void readKalibrImu(YamlOptionsReader root, RigCalibration& rig);

// cam0 and the IMU of a single file or text (the dataset presets, tests).
RigCamera parseKalibrCamchain(const std::string& text, const std::string& source);
RigImu parseKalibrImu(const std::string& text, const std::string& source);

}  // namespace adugs::data

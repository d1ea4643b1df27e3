#pragma once
// Writes a rig's calibration as other tools read it (`adugs calib convert`, `adugs calib show
// --json`). Every writer refuses (InputError naming the field) what its tool cannot hold: a
// camera model it has no implementation of, IMU intrinsics it has no keys for, per-sample noise
// without the rate.
//   kalibr    camchain-imucam.yaml (T_cam_imu, timeshift_cam_imu), imu.yaml (imu0:, with the
//             scale-misalignment blocks when the intrinsics are not the identity)
//   openvins  kalibr_imucam_chain.yaml (T_imu_cam) and kalibr_imu_chain.yaml (Tw, R_IMUtoGYRO, Ta,
//             R_IMUtoACC, Tg, model: kalibr), "%YAML:1.0" first as OpenVINS' parser wants; the
//             estimator_config.yaml naming them stays the user's
//   vins      config.yaml (VINS-Fusion: cam0_calib..., body_T_cam0 !!opencv-matrix, acc_n...) and
//             one camera file per camera (PINHOLE, MEI, KANNALA_BRANDT)
//   basalt    calib.json (pinhole, kb4, ds, eucm)
//   json      the layout of `adugs calib show --json` (doc/calibration_files.md)
#include <string>
#include <utility>
#include <vector>

#include "data/calibration.h"

namespace adugs::data {

// (file name, text) pairs, written by the caller into one folder.
using CalibrationFiles = std::vector<std::pair<std::string, std::string>>;

std::vector<std::string> calibrationWriterNames();  // kalibr, openvins, vins, basalt
CalibrationFiles formatCalibration(const RigCalibration& rig, const std::string& tool);
std::string formatCalibrationJson(const RigCalibration& rig);

}  // namespace adugs::data

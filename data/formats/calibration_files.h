#pragma once
// The calibration of a camera + IMU rig from the files users already have, recognised by their
// content, one file or several (a camchain and an imu file, a VINS config and its camera files):
//   Kalibr camchain / camchain-imucam and imu files (both forms), OpenVINS' variants of them
//   (data/formats/kalibr_calibration.h), VINS-Mono / VINS-Fusion configs
//   (data/formats/vins_calibration.h), Basalt calibration JSON (data/formats/basalt_calibration.h),
//   EuRoC/ASL sensor.yaml (data/formats/euroc_sensor_yaml.h).
// Keys that do not change the estimate are listed in RigCalibration::ignored_keys, never an
// error. A missing or wrong value, an unknown layout, a camera model the project cannot use, or
// two files that disagree (two different T_cam_imu, two different noise figures) is an InputError
// naming the file, the line and the field.
#include <ostream>
#include <string>
#include <vector>

#include "data/calibration.h"

namespace adugs::data {

RigCalibration readCalibrationFiles(const std::vector<std::string>& paths);
// One file's text (a preset embedded in the binary, a test), added to rig.
void readCalibrationText(const std::string& text, const std::string& source, RigCalibration& rig);

// One line per file with ignored keys: "note: FILE: ignored (no effect on the estimate): a, b".
void reportIgnoredKeys(const RigCalibration& rig, std::ostream& out);

}  // namespace adugs::data

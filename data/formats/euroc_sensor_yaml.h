#pragma once
// EuRoC ASL `sensor.yaml` files: cam0/sensor.yaml (camera) and imu0/sensor.yaml (IMU).
//
// Reading is strict (unknown keys, missing keys, wrong types, non-finite numbers, wrong counts are
// InputError naming the file, line and key). The OpenCV "%YAML:1.0" first line is accepted.
// T_BS (rows: 4, cols: 4, data: 16 numbers, row-major) must be a rigid transform: the rotation
// part orthonormal with det +1 within kRigidTolerance and the last row 0 0 0 1; the rotation is
// then re-orthonormalised so T_B_C is an exact isometry.
// Supported: camera_model pinhole; distortion_model radial-tangential (k1 k2 p1 p2),
// equidistant (k1 k2 k3 k4) or none, exactly 4 coefficients. adugs' optional keys `projection`
// (pinhole, omni, ds, eucm: data/calibration.h) and `projection_params` (xi / xi alpha / alpha
// beta) name a wide-angle projection before the distortion; they are written only when it is not
// pinhole, so pinhole files stay plain EuRoC.
// Writing produces EuRoC-style files (with the "%YAML:1.0" line) that read back to the same values.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "data/calibration.h"

namespace adugs::data {

// Max |R^T R - I| entry, |det R - 1| and last-row deviation accepted for T_BS; other tools'
// files (KAIST's in OpenVINS, 2e-5) are written with fewer digits and get the looser one.
constexpr double kRigidTolerance = 1e-5;
constexpr double kForeignRigidTolerance = 1e-4;

class YamlOptionsReader;
// The 4x4 matrix as a rigid transform (tolerance above, rotation re-orthonormalised); otherwise an
// InputError naming r's file and `key`.
Eigen::Isometry3d rigidTransform(const YamlOptionsReader& r, const std::string& key, const Eigen::Matrix4d& m,
                                 double tolerance = kRigidTolerance);

// camera_model (pinhole, or omni | ds | eucm whose projection_params the caller reads) and
// intrinsics [fu, fv, cu, cv] (EuRoC and Kalibr spell them alike).
void readPinholeIntrinsics(YamlOptionsReader& r, CameraCalibration* cam);

// Read from a file; `source` names the text in error messages for the *String variants.
CameraCalibration readEurocCameraYaml(const std::string& path);
CameraCalibration parseEurocCameraYaml(const std::string& text, const std::string& source);
ImuNoise readEurocImuYaml(const std::string& path);
ImuNoise parseEurocImuYaml(const std::string& text, const std::string& source);

// Write; numbers are printed in their shortest exact form. Throws InputError if the file cannot
// be written.
// comment: the file's `comment:` value (e.g. where the calibration came from).
// first_comment: lines ("# ...") put right after the %YAML:1.0 header (e.g. a calibration verdict).
std::string formatEurocCameraYaml(const CameraCalibration& camera, const std::string& comment = "written by adugs",
                                  const std::string& first_comment = "");
std::string formatEurocImuYaml(const ImuNoise& imu);
void writeEurocCameraYaml(const std::string& path, const CameraCalibration& camera,
                          const std::string& comment = "written by adugs", const std::string& first_comment = "");
void writeEurocImuYaml(const std::string& path, const ImuNoise& imu);

}  // namespace adugs::data

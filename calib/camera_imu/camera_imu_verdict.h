#pragma once
// Can a camera-IMU calibration be trusted? Physical plausibility (camera-to-IMU distance, IMU
// biases, time shift inside the search range, reprojection over the corners actually used),
// excitation and length of the recording, IMU coverage of the frames and the covariance, turned
// into a verdict (calib/calibration_verdict.h). How each default bound was chosen:
// doc/calibration.md, "Verdicts".
#include "calib/calibration_verdict.h"
#include "calib/camera_imu/camera_imu_calibrator.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct CameraImuVerdictOptions {
  // failed above (physically implausible for a camera rigidly mounted next to its IMU; raise
  // them for an unusual rig or IMU):
  double max_translation_m = 0.5;     // camera position in the IMU frame, norm
  double max_accel_bias = 1.0;        // m/s^2, norm of the mean accelerometer bias
  double max_gyro_bias = 0.5;         // rad/s, norm of the mean gyro bias
  double failed_rms_px = 5.0;         // reprojection RMS over the corners that project
  double failed_rotation_sigma_deg = 1.0;   // formal 1-sigma: not determined at all
  double failed_translation_sigma_m = 0.05;
  double failed_time_shift_sigma_s = 0.01;
  // weak below / above:
  double min_duration_s = 8;          // span of the frames with a board pose
  double min_weak_axis_rate = 0.05;   // rad/s RMS about the least excited axis
  double max_frames_outside_imu = 0.1;  // share of the frames with the target
  double max_rotation_sigma_deg = 0.1;  // formal 1-sigma of T_C_I's rotation, worst axis
  double max_translation_sigma_m = 0.005;  // formal 1-sigma of the camera position, worst axis
  double max_time_shift_sigma_s = 0.001;
  double max_rms_px = 1.5;
};

// Reads the keys above (unknown keys are InputError; the caller calls finish()).
void readCameraImuVerdictOptions(data::YamlOptionsReader& r, CameraImuVerdictOptions& o);

// calibration: the options the result was computed with (time-shift search range, excitation).
CalibrationVerdict judgeCameraImu(const CameraImuResult& result, const CameraImuOptions& calibration,
                                  const CameraImuVerdictOptions& options = {});

// The inputs' own verdicts: intrinsics or IMU noise figures that adugs wrote with verdict weak
// make the camera-IMU result weak too (it rests on them). Empty paths are skipped.
void judgeCameraImuInputs(CalibrationVerdict& verdict, const std::string& intrinsics_file,
                          const std::string& imu_noise_file);

}  // namespace adugs::calib

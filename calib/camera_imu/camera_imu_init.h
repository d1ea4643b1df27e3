#pragma once
// Initial guess of the camera-IMU calibration, before the continuous-time solve:
//   1. board pose per frame by PnP (camera pose in the target frame),
//   2. camera angular velocity between consecutive frames,
//   3. time offset from the cross-correlation of the angular speed norms (camera vs gyro),
//   4. rotation R_C_I aligning the two angular velocity series (Kabsch / Horn).
// Times are seconds since a common origin (the caller's), IMU clock for IMU samples and camera
// clock for frames; Kalibr's convention t_imu = t_cam + shift.
#include <Eigen/Geometry>
#include <vector>

#include "calib/calib_camera.h"
#include "calib/target/target_observation.h"

namespace adugs::calib {

struct BoardPose {
  double t = 0;     // camera clock [s]
  size_t view = 0;  // index into the views given to estimateBoardPoses
  Eigen::Quaterniond q_T_C = Eigen::Quaterniond::Identity();  // camera -> target
  Eigen::Vector3d p_T_C = Eigen::Vector3d::Zero();
  double rms_px = 0;  // PnP reprojection RMS
};

// PnP on the undistorted corners of every view with at least min_corners corners; views whose
// PnP RMS exceeds max_rms_px are dropped. t = (view.t_ns - origin_ns) * 1e-9.
std::vector<BoardPose> estimateBoardPoses(const std::vector<TargetObservation>& views,
                                          const CalibCamera& camera, int64_t origin_ns,
                                          int min_corners = 12, double max_rms_px = 3.0);

struct RateSample {
  double t = 0;
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // in the sensor's own frame [rad/s]
};

// Mean body rate between consecutive poses (Log(R_k^T R_k+1) / dt, at the mid time); pairs more
// than max_gap_s apart are skipped.
std::vector<RateSample> cameraAngularRates(const std::vector<BoardPose>& poses, double max_gap_s);

// Mean gyro reading over [t0, t1] (IMU samples sorted by time); false when no sample falls in it.
bool meanRate(const std::vector<RateSample>& imu, double t0, double t1, Eigen::Vector3d& mean);

// Shift maximising the correlation of |omega_cam(t)| and |omega_imu(t + shift)|, searched at the
// IMU sample period within +-max_shift_s. Frame-pair rates are compared with the gyro mean over
// the same (shifted) interval.
double timeOffsetByCorrelation(const std::vector<RateSample>& camera_rates,
                               const std::vector<RateSample>& imu, double frame_interval_s,
                               double max_shift_s);

// R_C_I minimising sum |omega_C - R_C_I omega_I|^2 over the frame pairs (gyro averaged over each
// pair's shifted interval). rms_out: the remaining residual RMS [rad/s].
Eigen::Matrix3d rotationFromAngularRates(const std::vector<RateSample>& camera_rates,
                                         const std::vector<RateSample>& imu,
                                         double frame_interval_s, double shift_s,
                                         double* rms_out = nullptr);

// Rotation excitation: RMS angular rate along the three principal axes of the gyro samples
// (sqrt of the eigenvalues of mean(w w^T)), largest first.
Eigen::Vector3d rotationExcitation(const std::vector<RateSample>& imu);

// Kabsch: the rotation R minimising sum |a_i - R b_i|^2.
Eigen::Matrix3d alignVectors(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b);

}  // namespace adugs::calib

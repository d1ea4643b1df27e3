#pragma once
// Camera-IMU calibration (Kalibr-like, continuous time): T_C_I, the time offset
// (t_imu = t_cam + shift), gravity in the target frame and constant IMU biases, from AprilGrid
// detections + IMU samples with the camera intrinsics fixed.
//
// Pipeline: PnP board poses -> gyro/camera rate correlation (time offset) and Kabsch (R_C_I) ->
// cumulative cubic B-spline for T_T_I(t) (knots at knot_rate_hz) initialised from the PnP poses ->
// one Ceres problem with all corner reprojections (IRLS Huber weights), gyro and accelerometer
// residuals weighted by the discrete noise sigma = density * sqrt(rate), piecewise-linear biases
// tied by their random walk.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "calib/imu_noise/allan_variance.h"
#include "calib/kalibr_yaml.h"
#include "calib/calib_camera.h"
#include "calib/target/target_observation.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct CameraImuOptions {
  double knot_rate_hz = 20;  // spline knots per second
  bool estimate_time_offset = true;
  double max_time_offset_s = 0.2;   // search range of the correlation
  double gravity = 9.81;            // |g| [m/s^2], fixed
  double bias_knot_interval_s = 5;  // piecewise-linear biases with a random-walk prior; 0: constant
  int frame_step = 1;               // use one frame in N
  int min_corners = 12;             // per frame
  int min_frames = 30;
  double pixel_sigma = 1.0;  // corner noise [px] (Kalibr's default)
  double huber_px = 1.5;     // IRLS Huber threshold on the corner error
  int robust_rounds = 2;     // solves; each after the first re-weights the corners
  int max_iterations = 40;   // per solve
  int threads = 2;
  double min_rotation_rate = 0.1;  // rad/s RMS: below, no rotation to align: not solved
  bool compute_covariance = true;  // 1-sigma of T_C_I and the time shift
  bool verbose = false;
};

// Reads the keys above (knot_rate_hz, estimate_time_offset, max_time_offset_s, gravity is not
// one: it comes with the IMU figures; threads and verbose are command-line flags). Unknown keys
// are InputError; the caller calls finish().
void readCameraImuOptions(data::YamlOptionsReader& r, CameraImuOptions& o);

// Where the inputs came from, for the error messages.
struct CameraImuSources {
  std::string corners = "corners";
  std::string imu = "imu";
  std::string intrinsics = "intrinsics";
};

struct TimedVector {
  double t = 0;  // IMU clock, seconds since the first IMU sample
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
};

struct CameraImuResult {
  Eigen::Isometry3d T_C_I = Eigen::Isometry3d::Identity();  // Kalibr T_cam_imu
  double time_shift_s = 0;                                  // t_imu = t_cam + shift
  Eigen::Vector3d gravity_T = Eigen::Vector3d::Zero();      // in the target frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();      // mean over the bias knots
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  struct BiasKnot {
    double t;  // IMU clock, seconds since the first IMU sample
    Eigen::Vector3d gyro, accel;
  };
  std::vector<BiasKnot> bias_knots;

  // Initial guess.
  Eigen::Matrix3d R_C_I_init = Eigen::Matrix3d::Identity();
  double time_shift_init_s = 0;
  double init_rate_rms = 0;  // Kabsch residual RMS [rad/s]

  // Residuals after the solve: per corner (norm, px), per IMU sample (vector).
  std::vector<double> corner_errors_px;
  std::vector<TimedVector> gyro_residuals;   // rad/s
  std::vector<TimedVector> accel_residuals;  // m/s^2
  double reprojection_rms_px = 0, gyro_rms = 0, accel_rms = 0;
  int corners_downweighted = 0;

  // corners_used: corners of the used frames that project into the camera at the solution (the
  // reprojection statistics are over these); corners_behind_camera: the others.
  bool solved = true;  // false: no rotation to align (excitation(0) < min_rotation_rate)
  int frames_with_target = 0, frames_outside_imu = 0;  // frames outside the IMU span: dropped
  double duration_s = 0;  // span of the frames with a board pose
  // 1-sigma from the covariance of the final problem (scaled by the residual variance):
  // rotation of T_C_I [rad] about its axes, camera position in the IMU frame [m], time shift [s].
  bool has_sigma = false;
  Eigen::Vector3d sigma_rotation = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_translation = Eigen::Vector3d::Zero();
  double sigma_time_shift_s = 0;
  double covariance_seconds = 0;
  int views_given = 0, frames_used = 0, corners_used = 0, imu_samples_used = 0;
  int corners_behind_camera = 0, corners_in_frames = 0;
  std::vector<std::string> solver_failures;  // solves that failed, in the tool's words
  bool final_solve_usable = true, final_solve_converged = true;
  int control_points = 0, iterations = 0;
  double pnp_rms_px = 0;
  Eigen::Vector3d excitation = Eigen::Vector3d::Zero();  // RMS rate per principal axis [rad/s]
  double seconds = 0;
};

// Throws data::InputError (naming sources.*) for too few frames, IMU not covering the frames,
// no rotation excitation, corners outside the intrinsics' image (files of different cameras).
CameraImuResult calibrateCameraImu(const std::vector<TargetObservation>& views,
                                   const CalibCamera& camera, const ImuRecording& imu,
                                   const ImuNoiseFigures& noise, const CameraImuOptions& options,
                                   const CameraImuSources& sources = {});

}  // namespace adugs::calib

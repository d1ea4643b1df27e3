#pragma once
// Options of the sliding-window estimator (SlidingWindowEstimator), defaults in code (tuned on
// the simulator and EuRoC), overridable from the `estimator:` map of a run config.
#include <string>

#include "vio/init/static_initializer.h"
#include "vio/init/visual_inertial_initializer.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::vio {

struct EstimatorOptions {
  int window_size = 10;              // frames kept (keyframes + the newest)
  double keyframe_parallax_px = 10;  // mean parallax (at focal_px) that makes a keyframe
  int keyframe_min_tracked = 30;     // fewer common features also makes a keyframe
  double pixel_sigma = 1.5;          // reprojection standard deviation [px]
  double huber_px = 1.0;             // robust loss threshold, in sigmas
  // The accelerometer's white-noise density the preintegration assumes: the IMU calibration's
  // (sensor.yaml, Kalibr) times this. A multirotor's rotor vibration is not in a datasheet
  // density: on the real V1_01 IMU the window's accelerometer residuals were ~40x their expected
  // size, where the simulator's (white noise at the stated density) were not; VINS-Mono and Basalt
  // run EuRoC with 8-40x the stated density. The EuRoC class sets it (data/config/euroc.yaml).
  double accel_noise_inflation = 1.0;
  // After each solve a landmark whose mean reprojection error over its non-host observations
  // exceeds this many pixels is removed and its feature id ignored while it stays tracked
  // (VINS-Mono's outliersRejection, same 3 px). Only landmarks seen in at least 3 frames are
  // judged. 0 turns it off.
  double outlier_reprojection_px = 3.0;
  int max_iterations = 8;
  // A solve also stops when an accepted step lowers the cost by less than this fraction.
  double solver_function_tolerance = 1e-4;
  // A guard only; when it triggers, results depend on machine load. adugs applies it to live
  // sources only (app/run_pipeline): playback solves every window to max_iterations.
  double max_solver_time_s = 0.2;
  double min_depth_m = 0.1, max_depth_m = 80.0;
  double min_triangulation_angle_deg = 1.0;  // rays of a new landmark must meet at least this
  // Zero-velocity updates while stationary (see zero_velocity_factor.h).
  bool zero_velocity_updates = true;
  double zero_velocity_sigma = 0.01;  // m/s
  // With them, the gyro bias held at the mean rate measured at rest (bias_prior_factor.h).
  bool gyro_bias_at_rest = true;
  // At a static initialisation the accelerometer bias is held where it was found with this sigma
  // (m/s^2; 0 = free): at rest the tilt and the horizontal bias are one unknown (bias_prior_factor.h).
  double static_init_accel_bias_sigma = 0.05;
  // The same prior on the first frame of a visual-inertial initialisation (m/s^2; 0 = free, as
  // VINS-Mono): there the bias and the scale trade off when the IMU accelerates little.
  double vi_init_accel_bias_sigma = 0.0;
  double stationary_parallax_px = 1.0;
  // First-estimate Jacobians (marginalization.h, linearizationPoint): the Jacobians on a frame in
  // the marginalisation prior are evaluated where the prior linearised it, so that the window
  // gains no information about its heading about gravity (doc/estimator.md).
  bool first_estimate_jacobians = false;
  // After each solve, keep the window's covariance of the newest frame's pose relative to the
  // oldest (EstimatorStats::relative_poses) for the consistency check against ground truth
  // (vio/eval/consistency.h). Costs one more linearisation and a factorisation per frame.
  bool report_relative_covariance = false;
  // Failure detection: a reset and re-initialisation instead of a diverged state.
  double max_accel_bias = 2.5;     // m/s^2
  double max_gyro_bias = 1.0;      // rad/s
  double max_speed = 30.0;         // m/s
  double max_position_jump = 5.0;  // m between the IMU prediction and the solved newest frame
  int min_tracked_features = 10;   // a frame with fewer features resets a moving estimator ...
  // ... once it has had fewer for this long: until then the window rides on the IMU and the few
  // features it has. A mover passing in front of the camera hides most of the scene for a
  // fraction of a second, and its mask with it (moving-box flight seed 2: 78 % of the image moving,
  // 90 % masked); a reset there re-initialises among the movers (doc/results.md, "... riding
  // through a mover that fills the view"). 0: reset at the first such frame.
  double few_features_max_s = 1.0;
  // Online camera-IMU extrinsic (VINS-Mono's ESTIMATE_EXTRINSIC = 1): T_B_C is refined in the
  // window while moving, held by a weak prior at the calibrated value (see pose_prior_factor.h).
  bool estimate_extrinsic = false;
  double extrinsic_prior_sigma_m = 0.01;
  double extrinsic_prior_sigma_deg = 3.0;
  // Camera-IMU time offset td (Kalibr's timeshift_cam_imu: t_imu = t_cam + td). time_offset_s is
  // the calibrated value; with estimate_time_offset (VINS-Mono's ESTIMATE_TD) td is refined in the
  // window, each observation shifted along its image velocity (reprojection_factor.h), held by a
  // weak prior at the calibrated value; a run whose estimate leaves +-max_time_offset_s resets.
  // td stays fixed until the estimator has been moving for time_offset_warmup_s since the
  // (re-)initialisation or the last stationary frame: freed right at take-off on the hybrid V1_01
  // it jumped to 34 ms and took a minute to come back.
  double time_offset_s = 0.0;
  bool estimate_time_offset = false;
  double time_offset_prior_sigma_s = 0.02;
  double max_time_offset_s = 0.1;
  double time_offset_warmup_s = 3.0;
  // IMU gaps: a frame whose interval since the previous frame has two IMU samples further apart
  // than this (or no sample within this of the frame) breaks the IMU chain: the estimator resets
  // and re-initialises; frames with no IMU near them are skipped (no pose).
  double max_imu_gap_s = 0.05;
  // The visual-inertial initialisation waits until the window spans this long: scale comes from
  // accelerations, and half a second of near-constant velocity (every frame a keyframe at
  // speed) underestimated it by 2x on the simulator.
  // (1.5 s: street/none 60 s ATE 0.125 m; 1.0 s: 0.47 m; 2.0 s: 0.20 m.)
  double init_min_span_s = 1.5;
  // Frames (counted like window_size) the window holds while it waits for the visual-inertial
  // initialisation; at most window_size. After it the window grows to window_size. A longer SfM
  // window spans more of the movers' motion: with 15, two of eighteen room/high runs started at
  // a fifth of the true scale and never recovered (doc/history.md, "The initialisation window").
  int init_window_size = 10;
  // After a reset (not an IMU gap), the last estimated state is carried by the IMU alone through
  // the outage; the re-initialised window is placed where it says (position and yaw, which the
  // new initialisation cannot know), so the trajectory continues instead of restarting at the
  // origin with an arbitrary heading. Outages longer than this start from the origin as before.
  double reset_dead_reckoning_max_s = 10.0;  // 0 = off
  StaticInitOptions static_init;
  InitOptions init;
};

// Reads the keys above (static_init:/init: as child maps); call finish() after.
void readEstimatorOptions(data::YamlOptionsReader& reader, EstimatorOptions* options);

}  // namespace adugs::vio

#pragma once
// Visual-inertial initialization from a moving start (VINS-Mono style): vision-only SfM on the
// first window of frames (essential matrix between the two frames with the most parallax,
// triangulation, PnP for the others, a small Ceres bundle adjustment), then visual-inertial
// alignment with the preintegrated IMU between consecutive frames:
//   1. gyro bias from the SfM relative rotations vs the preintegrated rotations (linear LS);
//   2. velocities, gravity in the first camera frame and the metric scale (linear LS);
//   3. gravity refinement with its norm fixed to |g| (2-DoF tangent correction, iterated).
// The result is expressed in a gravity-aligned world frame (z up, gravity (0, 0, -9.81)) whose
// origin is the first frame's body position and whose yaw is that of the first body frame.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "data/types.h"
#include "vio/imu/imu_preintegration.h"

namespace adugs::vio {

// One frame of the initialization window: its features and the IMU since the previous frame.
struct InitFrame {
  int64_t t_ns = 0;
  std::vector<int64_t> ids;                 // feature ids (FrameFeatures::ids)
  std::vector<Eigen::Vector2d> normalized;  // undistorted normalised coordinates, index-aligned
  // Preintegration from the previous frame's time to this one (nullptr for the first frame).
  std::shared_ptr<ImuPreintegration> imu_from_previous;
};

struct InitOptions {
  int min_frames = 8;                // window size needed before trying
  int min_common_features = 30;      // for the essential-matrix pair
  double min_parallax_px = 30.0;     // mean parallax (in pixels at focal_px) of the SfM pair
  double focal_px = 460.0;           // converts normalised parallax/reprojection to pixels
  double max_reprojection_px = 2.0;  // SfM landmarks with larger error after BA are dropped
  double min_scale = 1e-3;           // alignment rejects non-positive / tiny scales
  // |g_estimated| must lie within this of 9.81 before refinement.
  double gravity_norm_tolerance = 1.0;
  double max_gyro_bias = 0.5;  // rad/s; larger = failure
  // m/s^2: per-axis std over the intervals of the mean specific force (body frames, VINS-Mono's
  // excitation check, which VINS only prints); below this the IMU did not move: scale unobservable.
  // A resting IMU gives ~0.005 (EuRoC noise over 0.2 s intervals); 0 disables the check.
  double min_imu_excitation = 0.1;
  // Largest accepted standard deviation of the scale relative to the scale itself, as the
  // alignment's own fit gives it (LinearAlignment::scale_std). A window whose SfM followed moving
  // objects, or whose IMU accelerated too little, fits the IMU loosely: its scale can be off by
  // several times and the window never recovers. Refused, the initialisation waits for a better
  // window. 0 disables the check (the default: measured on the simulator only, where
  // data/config/sim.yaml sets 0.5; real cameras' windows were not measured).
  double max_scale_relative_std = 0.0;
};

struct InitResult {
  bool success = false;
  std::string failure_reason;                 // why not, for logs and the run summary
  std::vector<data::StampedPose> poses;       // T_W_B per window frame, metric, gravity-aligned
  std::vector<Eigen::Vector3d> velocities_W;  // per window frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // left at zero, as VINS-Mono
  double scale = 0;                                      // metric / SfM units
  double scale_relative_std = 0;  // the alignment's scale_std / scale (also set on that failure)
  std::map<int64_t, Eigen::Vector3d> landmarks_W;        // triangulated features, metric world
};

// T_B_C: camera-to-body extrinsic (p_B = T_B_C * p_C). Never throws on degenerate input: returns
// success = false with a reason (too few frames, too little parallax, SfM failed, bad scale,
// gravity far from 9.81, gyro bias too large...). The preintegrations in `frames` may be
// repropagated with the estimated gyro bias.
InitResult initializeVisualInertial(std::vector<InitFrame>& frames, const Eigen::Isometry3d& T_B_C,
                                    const InitOptions& options = {});

}  // namespace adugs::vio

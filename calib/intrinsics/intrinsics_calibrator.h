#pragma once
// Intrinsic calibration of one camera (any projection and distortion of CalibCamera) from
// AprilGrid (or any planar target) observations, in stages (calib/intrinsics/intrinsics_start for
// where it starts):
//   start    a focal length from the views' vanishing points, scored on the views with refit
//            poses and first distortion coefficient, never outside [0.2, 5] x the image width;
//            the projection's start values (omni xi 1, ds xi -0.2 alpha 0.5, eucm alpha 0.5
//            beta 1) with that focal length on the optical axis; planar PnP per view;
//   stage 1  focal lengths and the first lens parameter (pinhole: k1; omni: xi; ds, eucm:
//            alpha), principal point at the image centre, the others at their start;
//   stage 2  + the principal point;
//   stage 3  + every parameter of the model.
// Each stage is a Ceres bundle adjustment of the intrinsics and every view's pose, first with a
// Huber loss; outliers are rejected after each stage (stages 1-2: beyond outlier_sigma robust
// sigmas, each stage judging every corner again; stage 3: the 3-sigma rounds until none are
// left). The focal lengths stay inside the plausible range and the principal point inside the
// image (bounds); whether the result can be trusted is calib/intrinsics/intrinsics_verdict's job.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "calib/intrinsics/intrinsics_start.h"
#include "calib/calib_camera.h"
#include "calib/target/target_observation.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct IntrinsicsOptions {
  ProjectionModel projection = ProjectionModel::kPinhole;
  DistortionModel model = DistortionModel::kRadialTangential;  // omni: radtan or none; ds, eucm: none
  int min_views = 3;                 // fewer usable views is an error
  int min_corners_per_view = 12;     // views with fewer corners are skipped
  double outlier_sigma = 3.0;        // <= 0 disables outlier rejection
  int max_outlier_rounds = 4;
  int max_iterations = 100;          // per Ceres solve
  int threads = 2;
  double initial_focal_px = 0;       // 0: from the views (calib/intrinsics/intrinsics_start)
  double min_focal_over_width = 0.2; // plausible focal lengths: [min, max] x image width
  double max_focal_over_width = 5.0;
  bool compute_covariance = true;    // parameter standard deviations in the report
  double min_border_distance_px = 0; // corners closer to the image border are not used
  // Told what the calibration is doing (long sets take minutes); not from YAML.
  std::function<void(const std::string&)> progress;
};

// Reads the keys above (distortion_model as a name: radtan | equidistant, for a pinhole camera;
// the wide-angle models come from the command line's --model). Unknown keys are
// InputError; call r.finish() yourself if r holds more than these.
void readIntrinsicsOptions(data::YamlOptionsReader& r, IntrinsicsOptions& o);

struct ViewStats {
  int64_t t_ns = 0;
  std::string source;
  int corners = 0;
  int inliers = 0;
  double rms_px = 0;                                         // over inliers
  Eigen::Isometry3d T_C_T = Eigen::Isometry3d::Identity();   // target -> camera
};

struct CornerResidual {
  int view = 0;  // index into IntrinsicsResult::views
  int tag_id = 0;
  int corner = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();  // projected - measured, pixels
  bool inlier = true;
};

enum class IntrinsicsStage { kFocal, kPrincipalPoint, kDistortion };

struct IntrinsicsStageResult {
  IntrinsicsStage stage = IntrinsicsStage::kFocal;
  CalibCamera camera;  // after the stage
  int outliers = 0;      // corners the stage's rejection left out
};

struct IntrinsicsResult {
  CalibCamera camera;
  bool has_sigma = false;
  // 1-sigma and covariance of every parameter (CalibCamera::parameter indices: params, then
  // projection_params), scaled by the residual variance; 0 for those the model does not have.
  std::array<double, CalibCamera::kParameters> sigma{};
  Eigen::Matrix<double, CalibCamera::kParameters, CalibCamera::kParameters> covariance =
      Eigen::Matrix<double, CalibCamera::kParameters, CalibCamera::kParameters>::Zero();
  std::vector<ViewStats> views;   // the views used
  std::vector<CornerResidual> residuals;
  int views_given = 0;
  int views_skipped = 0;          // too few corners, or PnP failed
  int corners_used = 0;           // inliers in the final solve
  int outliers = 0;
  int border_excluded = 0;        // corners closer than min_border_distance_px to the border
  int outlier_rounds = 0;
  double initial_focal_px = 0;
  FocalStart focal_start;         // how the start was chosen (not filled for a user-given start)
  CalibCamera start_camera;       // where the staged solve started
  std::vector<IntrinsicsStageResult> stages;
  // The final model fitted to every usable corner (plain least squares, before the outlier
  // rounds): how far the result moves without the rejection says how much it rests on them.
  CalibCamera camera_all_corners;
  std::vector<std::string> solver_problems;  // failed solves, in the tool's words
  bool final_solve_usable = true;            // the last solve produced a solution
  bool final_solve_converged = true;         // ... and converged within max_iterations
  int solves = 0;
  int corners_not_projected = 0;  // inliers behind the camera at the solution (not in the stats)
  double rms_px = 0;              // sqrt(mean |e|^2) over inliers
  double mean_px = 0;             // mean |e|
  double max_px = 0;              // max |e| over inliers
  Eigen::Vector2d std_px = Eigen::Vector2d::Zero();  // per axis
  double solve_seconds = 0;       // all of calibrateIntrinsics
  double start_seconds = 0;       // of which finding the start
  int iterations = 0;
};

// Throws data::InputError (file "", field "views"/"corners") for too few usable views and
// std::invalid_argument for a bad image size.
IntrinsicsResult calibrateIntrinsics(const std::vector<TargetObservation>& views, int width,
                                     int height, const IntrinsicsOptions& options);

// How well a given camera explains the views: each view's pose is fitted (intrinsics fixed) and
// the RMS reprojection error over all corners of the usable views is returned (-1 if none).
// Used to compare a calibration with a reference (e.g. a published sensor.yaml).
double reprojectionRmsWithFixedIntrinsics(const std::vector<TargetObservation>& views,
                                          const CalibCamera& camera, int min_corners = 12);

}  // namespace adugs::calib

#pragma once
// Intrinsic calibration of one pinhole camera from AprilGrid (or any planar target)
// observations: Zhang-style initialisation (one focal length from the homographies' orthogonality
// constraints with the principal point at the image centre, median over views), planar PnP per
// view, then a Ceres bundle adjustment of all views (intrinsics + per-view pose), first with the
// distortion held at zero, then with it free. Corners off by more than outlier_sigma robust
// sigmas are dropped and the problem re-solved until none are left (or max_outlier_rounds).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "calib/camera_model.h"
#include "calib/target_observation.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct IntrinsicsOptions {
  DistortionModel model = DistortionModel::kRadialTangential;
  int min_views = 3;                 // fewer usable views is an error
  int min_corners_per_view = 12;     // views with fewer corners are skipped
  double outlier_sigma = 3.0;        // <= 0 disables outlier rejection
  int max_outlier_rounds = 4;
  int max_iterations = 100;          // per Ceres solve
  int threads = 2;
  double initial_focal_px = 0;       // 0: from the homographies
  bool compute_covariance = true;    // parameter standard deviations in the report
  double min_border_distance_px = 0; // corners closer to the image border are not used
};

// Reads the keys above (distortion_model as a name: radtan | equidistant). Unknown keys are
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

struct IntrinsicsResult {
  PinholeCamera camera;
  bool has_sigma = false;
  std::array<double, 8> sigma{};  // 1-sigma of params, scaled by the residual variance
  std::vector<ViewStats> views;   // the views used
  std::vector<CornerResidual> residuals;
  int views_given = 0;
  int views_skipped = 0;          // too few corners, or PnP failed
  int corners_used = 0;           // inliers in the final solve
  int outliers = 0;
  int border_excluded = 0;        // corners closer than min_border_distance_px to the border
  int outlier_rounds = 0;
  double initial_focal_px = 0;
  double rms_px = 0;              // sqrt(mean |e|^2) over inliers
  double mean_px = 0;             // mean |e|
  double max_px = 0;              // max |e| over inliers
  Eigen::Vector2d std_px = Eigen::Vector2d::Zero();  // per axis
  double solve_seconds = 0;
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
                                          const PinholeCamera& camera, int min_corners = 12);

}  // namespace adugs::calib

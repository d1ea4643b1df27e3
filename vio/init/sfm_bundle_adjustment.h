#pragma once
// Bundle adjustment of the initialization SfM (Ceres): camera poses T_R_C and points in the
// reference camera frame R, reprojection residuals in pixels (normalised error * focal) with a
// Huber loss. Gauge: the reference camera is held fixed (rotation and position) and the position
// of the second camera of the essential-matrix pair stays on the sphere of its current radius
// (ceres::SphereManifold), which fixes the scale to the pair's baseline length.
#include <cstdint>
#include <map>
#include <vector>

#include "vio/init/sfm_geometry.h"

namespace adugs::vio {

struct SfmObservation {
  int frame = 0;
  Eigen::Vector2d normalized;
};

struct SfmBundleProblem {
  std::vector<SfmPose> poses;                                   // per frame, in/out
  std::map<int64_t, Eigen::Vector3d> points;                    // in/out
  std::map<int64_t, std::vector<SfmObservation>> observations;  // per point id
  int fixed_frame = 0;                                          // fully fixed
  int fixed_position_frame = 1;  // distance to the reference fixed (scale gauge)
};

struct SfmBundleOptions {
  double focal_px = 460.0;
  double huber_px = 1.0;
  int max_iterations = 50;
};

// Refines poses and points in place. false if Ceres reports a failure or the result is not finite.
bool bundleAdjust(SfmBundleProblem& problem, const SfmBundleOptions& options);

}  // namespace adugs::vio

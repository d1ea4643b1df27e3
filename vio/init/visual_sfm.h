#pragma once
// Vision-only structure from motion over the initialization window (up to scale):
//   1. the pair (0, k): frame 0 is the reference; k is the frame with the largest translation
//      parallax (feature motion a pure rotation cannot explain) among those with enough common
//      features and raw parallax;
//   2. essential matrix (RANSAC) and recoverPose on normalised points; |baseline| = 1;
//   3. triangulation of the pair, then frames outward from the pair by PnP (RANSAC) on the
//      known points, triangulating new points after each frame;
//   4. bundle adjustment (frame 0 fixed, frame k's position fixed), outliers dropped.
// Never throws: failures come back as success = false with a reason.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "vio/init/sfm_geometry.h"

namespace adugs::vio {

struct SfmFrameObservations {
  std::vector<int64_t> ids;
  std::vector<Eigen::Vector2d> normalized;  // index-aligned with ids
};

struct VisualSfmOptions {
  int min_common_features = 30;
  double min_parallax_px = 30.0;             // raw mean feature motion of the pair
  double min_translation_parallax_px = 8.0;  // rotation-compensated; pure rotation gives ~0
  double focal_px = 460.0;
  double max_reprojection_px = 2.0;
  int min_pnp_inliers = 12;
  int min_landmarks = 20;  // after BA and outlier removal
};

struct VisualSfmResult {
  bool success = false;
  std::string failure_reason;
  int pair_frame = -1;                        // k of the pair (0, k)
  std::vector<SfmPose> poses;                 // T_C0_Ck per frame (scale: |p_C0_Ck| = 1)
  std::map<int64_t, Eigen::Vector3d> points;  // in the frame-0 camera frame, same scale
  double pair_parallax_px = 0;                // raw, of the chosen pair
  double pair_translation_parallax_px = 0;    // rotation-compensated, of the chosen pair
  double mean_reprojection_px = 0;            // after BA, over the kept landmarks
};

VisualSfmResult runVisualSfm(const std::vector<SfmFrameObservations>& frames,
                             const VisualSfmOptions& options = {});

}  // namespace adugs::vio

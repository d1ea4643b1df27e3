#pragma once
// Where the intrinsic calibration starts: a focal length (and the first distortion coefficient)
// for the camera model with the principal point at the image centre.
//
// Candidates come from each view's homography H (target plane -> pixels centred on the image
// centre): two pairs of the board's vanishing points are images of orthogonal directions, its
// rows and columns (h1, h2) and its two diagonals (h1 + h2, h1 - h2). With K = diag(f, f, 1),
// v_a^T K^-T K^-1 v_b = 0 gives f^2 = -(x_a x_b + y_a y_b) / (w_a w_b). A view seen nearly
// face-on has its vanishing points at infinity (w -> 0) and gives no candidate or a wild one:
// everything outside [min, max] x the image width is dropped, and a geometric ladder over that
// range (ratio 1.25) is added so there is always a candidate near the truth.
//
// Each candidate is scored on the views (up to max_views_scored, evenly spread) with refit poses
// AND a refit first distortion coefficient (k1 of either model), robustly (Huber, 2 px): the
// distortion-free score cannot see the focal length on face-on views of a wide-angle lens (on
// EuRoC cam_april it is lowest at 1800 px, the lens has 460 px; with k1 fitted it is lowest at
// 550 px). The best candidate is refined by a golden-section search within a ladder step.
#include <vector>

#include <Eigen/Core>

#include "calib/calib_camera.h"
#include "calib/target/target_observation.h"

namespace adugs::calib {

struct FocalStartOptions {
  double min_focal_over_width = 0.2;  // plausible focal lengths: [min, max] x image width
  double max_focal_over_width = 5.0;
  int max_candidates = 16;            // candidates from the views kept (evenly spread quantiles)
  int max_views_scored = 20;          // more views are scored on an evenly spread subset
  int threads = 2;
};

struct FocalStart {
  double focal_px = 0;
  double first_distortion = 0;  // the refit k1 at focal_px
  double score_px = 0;          // robust RMS reprojection error at focal_px
  int view_candidates = 0;      // candidates from the views inside the plausible range
  int candidates_scored = 0;    // including the ladder and the refinement
  int views_scored = 0;
};

// Focal lengths from one homography (0, 1 or 2 values, not range-checked): rows/columns and
// diagonals. H maps target (x, y, 1) to pixel coordinates centred on the principal point.
std::vector<double> focalCandidatesFromHomography(const Eigen::Matrix3d& H);

// Robust RMS reprojection error [px] of camera (focal f, principal point (cu, cv), the model's
// first distortion coefficient refit, the others 0) over the views, every pose refit. Views whose
// pose PnP cannot find are left out; none left: +infinity. k1 (optional): the refit coefficient.
double scoreFocal(const std::vector<const TargetObservation*>& views, DistortionModel model,
                  double f, double cu, double cv, double* k1 = nullptr, int threads = 1);

// Views need >= 4 corners. Throws std::invalid_argument for a bad size or no such view.
// model: the distortion of the pinhole the candidates are scored with (startDistortion).
FocalStart findFocalStart(const std::vector<const TargetObservation*>& views, int width,
                          int height, DistortionModel model, const FocalStartOptions& options = {});

// The pinhole distortion the focal search scores with for a camera's model: its own for pinhole
// cameras, equidistant for the wide-angle projections (one coefficient follows a wide lens to
// 90 degrees; radtan's k1 folds back before it).
DistortionModel startDistortion(const CalibCamera& model);

// The camera the staged solve starts from, for model's projection and distortion (its values
// are not used): principal point at the image centre, focal length on the optical axis = the
// start's focal_px, and the projection's start values (Kalibr's omni xi = 1; Basalt's ds xi -0.2,
// alpha 0.5 and eucm alpha 0.5, beta 1); pinhole: k1 = the start's first_distortion.
CalibCamera startCamera(const CalibCamera& model, int width, int height, const FocalStart& start);

}  // namespace adugs::calib

#pragma once
// Can an intrinsic calibration be trusted? Coverage of the views (image area share, board tilts),
// the covariance, the residuals and physical plausibility turned into a verdict (see
// calib/calibration_verdict.h). How each default bound was chosen: doc/calibration.md,
// "Verdicts".
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/calibration_verdict.h"
#include "calib/intrinsics/intrinsics_calibrator.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct IntrinsicsCoverage {
  int cells_x = 0, cells_y = 0;         // the image cut into cells_x x cells_y cells
  std::vector<int> corners_per_cell;    // inlier corners per cell, row-major
  double image_share = 0;               // share of the cells holding an inlier corner
  // Per used view: angle between the board normal and the optical axis, and the board normal's
  // direction as tilts about the camera's x and y axes (degrees).
  std::vector<double> view_tilt_deg;
  std::vector<Eigen::Vector2d> view_tilt_xy_deg;
  double max_tilt_deg = 0;
  double tilt_spread_deg = 0;           // largest angle between two views' board normals
};

// columns: cells across the image width (rows follow from the aspect ratio).
IntrinsicsCoverage measureCoverage(const IntrinsicsResult& result, int columns = 10);

struct IntrinsicsVerdictOptions {
  // weak below / above:
  int min_views = 10;
  double min_image_share = 0.5;          // of the coverage cells
  double min_tilt_spread_deg = 25;       // largest angle between two views' board normals
  double max_focal_rel_sigma = 0.002;    // formal 1-sigma of fu, fv relative to their value
  double max_principal_point_rel_sigma = 0.003;  // formal 1-sigma of pu, pv relative to the width
  double max_distortion_sigma_px = 1.0;  // 1-sigma of the distortion (all coefficients, with
                                         // their correlations) as pixels at the farthest corner
                                         // the views cover
  double max_rms_px = 1.0;
  // failed above:
  double failed_rms_px = 10.0;
  double failed_focal_rel_sigma = 0.10;  // the focal length is not determined at all
  int coverage_columns = 10;
};

// Reads the keys above (unknown keys are InputError; the caller calls finish()).
void readIntrinsicsVerdictOptions(data::YamlOptionsReader& r, IntrinsicsVerdictOptions& o);

// Where the lens model stops being one-to-one: the largest normalised image radius
// |((u - pu) / fu, (v - pv) / fv)| that rays along the x axis reach before the projection folds
// back or stops (+infinity when it never does up to ~89 degrees off-axis).
double distortionFoldRadius(const CalibCamera& camera);

// The focal length the corners determine along axis i (0: u, 1: v), with its formal 1-sigma
// (0 without a covariance): fu, fv for pinhole and EUCM cameras; for omni and ds the focal length
// on the optical axis, fu / (1 + xi): their xi trades against fu along a flat valley, and the
// views fix the two only together.
struct DeterminedFocal {
  std::string name;  // "fu" or "fu / (1 + xi)"
  double px = 0;
  double sigma_px = 0;
};
DeterminedFocal determinedFocal(const IntrinsicsResult& result, int axis);

struct IntrinsicsJudgement {
  CalibrationVerdict verdict;
  IntrinsicsCoverage coverage;
  // Per parameter, CalibCamera::parameter indices (fu fv pu pv d0..d3, then the projection's).
  std::array<bool, CalibCamera::kParameters> poorly_determined{};
  // 1-sigma of the projection at the farthest corner the views cover [px]: of each parameter
  // alone, and of the lens parameters (distortion coefficients and projection parameters)
  // together (their covariance block: k1..k4 of a fisheye, or xi and alpha of a double sphere,
  // trade off against each other, one alone says little).
  std::array<double, CalibCamera::kParameters> sigma_effect_px{};
  double distortion_sigma_px = 0;
  // final - every-corner solution, per parameter (reported: how much the result rests on the
  // outlier rejection)
  std::array<double, CalibCamera::kParameters> rejection_shift{};
};

// calibration: the options the result was computed with (plausible focal range).
IntrinsicsJudgement judgeIntrinsics(const IntrinsicsResult& result,
                                    const IntrinsicsOptions& calibration,
                                    const IntrinsicsVerdictOptions& options = {});

}  // namespace adugs::calib

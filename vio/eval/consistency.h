#pragma once
// Consistency of the estimator's covariance (NEES, the normalised estimation error squared, as
// OpenVINS' ov_eval reports it for its filter): does the error the window makes stay within the
// uncertainty it claims? For each RelativePoseEstimate (newest window frame relative to the oldest,
// vio/estimator/relative_pose_estimate.h) the error against the ground truth at the same two times,
// e = [R_true_from^T (p_est - p_true) ..., Log(R_true^-1 R_est)], and its NEES e^T P^-1 e. A
// consistent estimator averages the degrees of freedom (6 for the pose, 3 for the position, 1 for
// the heading about gravity); more means it claims more certainty than it has (overconfident), and
// an overconfident window drifts: it refuses the corrections the measurements ask for.
#include <cstdint>
#include <vector>

#include "data/types.h"
#include "vio/estimator/relative_pose_estimate.h"

namespace adugs::vio {

struct ConsistencyResult {
  size_t count = 0;           // estimates matched with the ground truth at both ends
  double nees_pose = 0;       // mean NEES of the 6-DoF relative pose (consistent: 6)
  double nees_position = 0;   // of its position (3)
  double nees_yaw = 0;        // of its rotation about gravity (1)
  double within_95 = 0;       // share of pose NEES under the chi-square 95 % bound (12.59; consistent: 0.95)
};

// Ground-truth poses are matched by time within max_dt_ns (no interpolation); estimates without
// a match at both ends, or whose covariance is not positive definite, are left out.
ConsistencyResult evaluateConsistency(const std::vector<RelativePoseEstimate>& estimates,
                                      const data::Trajectory& gt, int64_t max_dt_ns = 10'000'000);

}  // namespace adugs::vio

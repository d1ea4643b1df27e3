#pragma once
// Whole evaluation of an estimated trajectory against ground truth, as `adugs eval` runs it:
// associate by time -> align (se3 / sim3 / posyaw / none) -> ATE, RPE and OpenLORIS' correct rate.
// Only the part of the estimate that the ground truth covers is evaluated: an estimated pose is
// used when a ground-truth pose lies within max_dt of it (no interpolation, no extrapolation), so
// poses more than max_dt before the ground truth starts, after it ends, or inside a gap of it
// (TUM-VI's mocap sees only the start and the end of most sequences) are left out of every figure.
#include <cstdint>
#include <string>
#include <vector>

#include "data/types.h"
#include "vio/eval/correct_rate.h"
#include "vio/eval/trajectory_alignment.h"
#include "vio/eval/trajectory_metrics.h"

namespace adugs::vio {

struct EvalOptions {
  int64_t max_dt_ns = 10'000'000;  // association: max |t_est - t_gt| (evo's default 0.01 s)
  AlignMode align = AlignMode::kSe3;
  int align_frames = -1;              // align on the first N matched pairs; <= 0: all
  // The estimate's poses less than this long after its first pose, and the ground truth before
  // them, are left out of everything (evo's --t_start, relative to the estimate): after a moving start the window spends a few
  // seconds correcting the initialisation's scale and velocity, and on a short run that transient
  // can be most of the ATE. 0: every pose.
  double skip_first_s = 0;
  std::vector<double> rpe_lengths_m;  // empty: 10..50 % of the matched ground-truth path length
  double rpe_length_tolerance = 0.1;  // a segment's travelled distance within L * (1 +- this)
  CorrectRateOptions correct_rate;    // thresholds of a correct pose (1 m, 30 deg)
};

struct EvalResult {
  size_t est_poses = 0;  // input sizes (before skip_first_s)
  size_t gt_poses = 0;
  std::vector<Association> pairs;
  data::Trajectory est_matched;  // est poses of the pairs, in the estimate's frame
  data::Trajectory gt_matched;   // their ground-truth poses
  data::Trajectory est_aligned;  // est_matched mapped into the ground-truth frame
  AlignMode align_mode = AlignMode::kSe3;
  SimilarityTransform T_G_E;
  size_t align_pairs_used = 0;
  double gt_length_m = 0.0;  // path length of gt_matched
  AteResult ate;
  std::vector<RpeResult> rpe;
  CorrectRateResult correct_rate;  // over the matched poses, times of the estimate
};

// Throws std::invalid_argument when nothing can be evaluated (no pair within max_dt, degenerate
// alignment, bad options); the message says why.
EvalResult evaluateTrajectory(const data::Trajectory& est, const data::Trajectory& gt,
                              const EvalOptions& options = {});

}  // namespace adugs::vio

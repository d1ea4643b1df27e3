#pragma once
// What `adugs run` writes next to the trajectory: summary.yaml (counts, timing) and, when the
// sequence has ground truth, the evaluation (ATE and OpenLORIS correct rate printed and in
// summary.yaml, eval.png).
#include <cstddef>
#include <string>
#include <vector>

#include "vio/estimator/relative_pose_estimate.h"

namespace adugs::app {

struct RunStats {
  std::string command = "run";  // run | live
  size_t frames = 0;
  size_t imu_samples = 0;
  size_t poses = 0;
  size_t skipped_frames = 0;
  double sequence_s = 0.0;    // sequence time spanned by the frames
  double wall_s = 0.0;        // processing time
  std::string extra_summary;  // estimator-specific YAML lines appended to summary.yaml
  // The window's relative poses with their covariance (estimator: report_relative_covariance):
  // with ground truth, their NEES goes into summary.yaml (vio/eval/consistency.h). May be null.
  const std::vector<vio::RelativePoseEstimate>* relative_poses = nullptr;
};

// Writes out_dir/summary.yaml, evaluates against gt_path when not empty (se3 alignment), prints
// a short report on stdout. trajectory_path "": no trajectory (vision-only runs).
void writeRunOutputs(const std::string& out_dir, const std::string& estimator,
                     const std::string& trajectory_path, const std::string& gt_path,
                     const RunStats& stats);

}  // namespace adugs::app

#pragma once
// Time association of an estimated trajectory with ground truth, and the alignment of the
// estimate's world frame E onto the ground-truth world frame G before errors are measured.
//
// Alignment modes (as evo / ov_eval / rpg_trajectory_evaluation):
//   se3     rotation + translation (Umeyama without scale)
//   sim3    rotation + translation + scale (Umeyama with scale)
//   posyaw  translation + rotation about the gravity (z) axis only: the 4 DoF a VIO cannot observe
//   none    identity
// With align_frames == 1, se3 and posyaw use the first pose pair (orientation included) instead
// of a point-set fit.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "data/types.h"

namespace adugs::vio {

enum class AlignMode { kSe3, kSim3, kPosYaw, kNone };

// "se3", "sim3", "posyaw", "none". parseAlignMode throws std::invalid_argument on anything else.
AlignMode parseAlignMode(const std::string& name);
const char* alignModeName(AlignMode mode);

// p_G = scale * R_G_E * p_E + t_G_E; orientations q_G_B = q_G_E * q_E_B.
struct SimilarityTransform {
  Eigen::Matrix3d R_G_E = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_G_E = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p_E) const { return scale * (R_G_E * p_E) + t_G_E; }
  // How much longer the estimate is than the ground truth, in %: an estimate 1 % long is shrunk by
  // scale = 1 / 1.01 (+1), one 1 % short grown by 1 / 0.99 (-1).
  double lengthErrorPercent() const { return 100.0 * (1.0 / scale - 1.0); }
  data::StampedPose apply(const data::StampedPose& pose_E) const;
  data::Trajectory apply(const data::Trajectory& trajectory_E) const;
};

// One matched pair: est[est_index] and gt[gt_index].
struct Association {
  size_t est_index = 0;
  size_t gt_index = 0;
};

// Matches each estimated pose with the ground-truth pose nearest in time, kept if
// |dt| <= max_dt_ns. Matches are one-to-one: when several estimates pick the same ground-truth
// pose, the one closest in time keeps it (the earlier one on a tie). Pairs come in time order.
// Both trajectories must be sorted by time (std::invalid_argument otherwise).
// (evo's sync.associate_trajectories gives the same pairs whenever its matches are unique.)
std::vector<Association> associate(const data::Trajectory& est, const data::Trajectory& gt,
                                   int64_t max_dt_ns);

// Least-squares fit gt_i ~ T(est_i) over the first n positions (n <= 0 or n > size: all).
// Throws std::invalid_argument for empty or mismatched input, and for a degenerate point set
// (fewer than 3 non-collinear positions for se3/sim3, all positions equal for sim3).
SimilarityTransform alignUmeyama(const std::vector<Eigen::Vector3d>& est,
                                 const std::vector<Eigen::Vector3d>& gt, bool with_scale,
                                 int n = -1);
// Translation + yaw (rotation about z) that best fits gt_i ~ T(est_i); never degenerate.
SimilarityTransform alignPositionYaw(const std::vector<Eigen::Vector3d>& est,
                                     const std::vector<Eigen::Vector3d>& gt, int n = -1);

// Alignment of matched trajectories (est[i] <-> gt[i]) with the given mode, using the first
// align_frames pairs (<= 0: all). align_frames == 1 aligns the first poses exactly (se3) or
// their yaw and position (posyaw); sim3 needs at least 3 pairs.
SimilarityTransform alignTrajectory(const data::Trajectory& est, const data::Trajectory& gt,
                                    AlignMode mode, int align_frames = -1);

}  // namespace adugs::vio

#pragma once
// Error metrics between an aligned estimate and ground truth, pose i matched with pose i.
//
// ATE (absolute trajectory error): per pose |p_gt - p_est| (evo_ape translation_part) and the
// rotation angle of R_gt^T R_est in degrees (evo_ape rotation_angle_deg).
// RPE (relative pose error) over travelled distance, as rpg_trajectory_evaluation / ov_eval:
// for each length L and every start pose i, the end pose j is the one whose ground-truth distance
// travelled since i is closest to L (kept within tolerance * L; the path must reach i + L). With relative motions
// T_gt = T_gt,i^-1 T_gt,j and T_est = T_est,i^-1 T_est,j, the error E = T_gt^-1 T_est gives
// translation |t(E)| in m and in % of the distance actually travelled, rotation angle(R(E)) and
// yaw error (rotation about world z of R(E) expressed in the ground-truth world frame), in degrees.
#include <cstdint>
#include <vector>

#include "data/types.h"

namespace adugs::vio {

// Statistics as evo's (std is the population standard deviation); all zero when count == 0.
struct ErrorStats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  size_t count = 0;
};

ErrorStats computeStats(const std::vector<double>& values);

struct AteResult {
  std::vector<int64_t> t_ns;          // time of each matched pose
  std::vector<double> translation_m;  // |p_gt - p_est|
  std::vector<double> rotation_deg;   // angle(R_gt^T R_est)
  ErrorStats translation;             // m
  ErrorStats rotation;                // deg
};

// est_aligned[i] is compared with gt[i]; std::invalid_argument if sizes differ or are zero.
AteResult computeAte(const data::Trajectory& est_aligned, const data::Trajectory& gt);

struct RpeResult {
  double length_m = 0.0;  // nominal segment length
  ErrorStats translation_m;
  ErrorStats translation_pct;  // of the ground-truth distance travelled over each segment
  ErrorStats rotation_deg;
  ErrorStats yaw_deg;
};

// Sum of |p_i+1 - p_i|.
double pathLength(const data::Trajectory& trajectory);

// 10, 20, 30, 40, 50 % of the path length, rounded to 2 significant digits; empty if length 0.
std::vector<double> defaultRpeLengths(double path_length_m);

// One result per length (in the given order); a length with no segment gets count 0.
// Lengths must be > 0 (std::invalid_argument otherwise).
std::vector<RpeResult> computeRpe(const data::Trajectory& est_aligned, const data::Trajectory& gt,
                                  const std::vector<double>& lengths_m,
                                  double length_tolerance = 0.1);

}  // namespace adugs::vio

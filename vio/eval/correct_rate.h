#pragma once
// OpenLORIS-Scene's correct rate (CR): the share of the sequence's time during which the
// estimate was right, as the benchmark's evaluate.py computes it.
//
// Input: the matched poses after alignment (time of the ESTIMATED pose, its position error and
// its orientation error against ground truth), and the ground truth's first and last time.
//   correct pose   position error <= max_position_m and orientation error <= max_angle_deg
//   t_end          max(last matched estimate time, last ground-truth time)
//   gap_i          time to the next matched estimate (the last one: to t_end), at most max_gap
//   correct time   sum of gap_i over the correct poses
//   CR             correct time / (t_end - first ground-truth time)
// Poses without ground truth (not matched) take no part: they are neither correct nor a "next
// pose". A pose missing for longer than max_gap counts as lost time.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace adugs::vio {

struct CorrectRateOptions {
  double max_position_m = 1.0;  // OpenLORIS README's example thresholds (-t 1 -o 30)
  double max_angle_deg = 30.0;
  int64_t max_gap_ns = 1'000'000'000;  // evaluate.py's --max-pose-interval (1 s)
};

struct CorrectRateResult {
  double correct_rate = 0.0;  // NaN when the span is not positive
  double correct_time_s = 0.0;
  double span_s = 0.0;  // t_end - first ground-truth time
  size_t correct_poses = 0;
  size_t poses = 0;  // matched poses judged
};

// est_t_ns must be strictly increasing and the three vectors of equal size
// (std::invalid_argument otherwise); the thresholds must be >= 0 and max_gap_ns > 0.
CorrectRateResult computeCorrectRate(const std::vector<int64_t>& est_t_ns,
                                     const std::vector<double>& position_error_m,
                                     const std::vector<double>& angle_error_deg,
                                     int64_t gt_first_ns, int64_t gt_last_ns,
                                     const CorrectRateOptions& options = {});

}  // namespace adugs::vio

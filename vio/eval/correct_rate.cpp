#include "vio/eval/correct_rate.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "data/types.h"

namespace adugs::vio {

CorrectRateResult computeCorrectRate(const std::vector<int64_t>& est_t_ns,
                                     const std::vector<double>& position_error_m,
                                     const std::vector<double>& angle_error_deg,
                                     int64_t gt_first_ns, int64_t gt_last_ns,
                                     const CorrectRateOptions& options) {
  const size_t n = est_t_ns.size();
  if (position_error_m.size() != n || angle_error_deg.size() != n)
    throw std::invalid_argument("correct rate: " + std::to_string(n) + " times but " +
                                std::to_string(position_error_m.size()) + " position and " +
                                std::to_string(angle_error_deg.size()) + " angle errors");
  if (!(options.max_position_m >= 0.0) || !(options.max_angle_deg >= 0.0))
    throw std::invalid_argument("correct rate: thresholds must be >= 0");
  if (options.max_gap_ns <= 0) throw std::invalid_argument("correct rate: max gap must be > 0");
  if (gt_last_ns < gt_first_ns)
    throw std::invalid_argument("correct rate: ground truth ends before it starts");
  for (size_t i = 1; i < n; ++i)
    if (est_t_ns[i] <= est_t_ns[i - 1])
      throw std::invalid_argument("correct rate: estimate times must be strictly increasing");

  CorrectRateResult r;
  r.poses = n;
  const int64_t t_end = n ? std::max(est_t_ns.back(), gt_last_ns) : gt_last_ns;
  int64_t correct_ns = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(position_error_m[i] <= options.max_position_m) ||
        !(angle_error_deg[i] <= options.max_angle_deg))
      continue;
    ++r.correct_poses;
    const int64_t next = i + 1 < n ? est_t_ns[i + 1] : t_end;
    correct_ns += std::min(next - est_t_ns[i], options.max_gap_ns);
  }
  const int64_t span_ns = t_end - gt_first_ns;
  r.correct_time_s = data::nsToSec(correct_ns);
  r.span_s = data::nsToSec(span_ns);
  r.correct_rate =
      span_ns > 0 ? r.correct_time_s / r.span_s : std::numeric_limits<double>::quiet_NaN();
  return r;
}

}  // namespace adugs::vio

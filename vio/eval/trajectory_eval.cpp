#include "vio/eval/trajectory_eval.h"

#include <cstdio>
#include <stdexcept>

namespace adugs::vio {
namespace {

std::string timeRange(const data::Trajectory& t) {
  if (t.empty()) return "(empty)";
  char buf[96];
  std::snprintf(buf, sizeof(buf), "[%.3f, %.3f] s", data::nsToSec(t.front().t_ns),
                data::nsToSec(t.back().t_ns));
  return buf;
}

}  // namespace

EvalResult evaluateTrajectory(const data::Trajectory& est, const data::Trajectory& gt,
                              const EvalOptions& options) {
  if (options.max_dt_ns < 0) throw std::invalid_argument("max dt must be >= 0");
  if (!(options.skip_first_s >= 0)) throw std::invalid_argument("the time skipped at the start must be >= 0 s");
  if (options.skip_first_s > 0 && !est.empty()) {
    // Both trajectories cropped, so that the correct rate's span starts where the evaluation does.
    const int64_t from_ns = est.front().t_ns + data::secToNs(options.skip_first_s);
    data::Trajectory est_kept, gt_kept;
    for (const data::StampedPose& pose : est)
      if (pose.t_ns >= from_ns) est_kept.push_back(pose);
    for (const data::StampedPose& pose : gt)
      if (pose.t_ns >= from_ns - options.max_dt_ns) gt_kept.push_back(pose);
    if (est_kept.empty()) {
      char buf[128];
      std::snprintf(buf, sizeof(buf), "nothing left to evaluate: the estimate spans %.3f s, all of it within the %g s skipped",
                    data::nsToSec(est.back().t_ns - est.front().t_ns), options.skip_first_s);
      throw std::invalid_argument(buf);
    }
    EvalOptions rest = options;
    rest.skip_first_s = 0;
    EvalResult cropped = evaluateTrajectory(est_kept, gt_kept, rest);
    cropped.est_poses = est.size();
    cropped.gt_poses = gt.size();
    return cropped;
  }
  EvalResult r;
  r.est_poses = est.size();
  r.gt_poses = gt.size();
  r.pairs = associate(est, gt, options.max_dt_ns);
  if (r.pairs.empty()) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.6g s", data::nsToSec(options.max_dt_ns));
    throw std::invalid_argument("no associated poses: no estimated pose lies within " +
                                std::string(buf) + " of a ground-truth pose (estimate spans " +
                                timeRange(est) + ", ground truth spans " + timeRange(gt) +
                                "; same clock and units?)");
  }
  for (const Association& a : r.pairs) {
    r.est_matched.push_back(est[a.est_index]);
    r.gt_matched.push_back(gt[a.gt_index]);
  }
  r.align_mode = options.align;
  r.T_G_E = alignTrajectory(r.est_matched, r.gt_matched, options.align, options.align_frames);
  r.align_pairs_used =
      options.align == AlignMode::kNone ? 0
      : (options.align_frames <= 0 || static_cast<size_t>(options.align_frames) > r.pairs.size())
          ? r.pairs.size()
          : static_cast<size_t>(options.align_frames);
  r.est_aligned = r.T_G_E.apply(r.est_matched);
  r.gt_length_m = pathLength(r.gt_matched);
  r.ate = computeAte(r.est_aligned, r.gt_matched);
  const std::vector<double> lengths =
      options.rpe_lengths_m.empty() ? defaultRpeLengths(r.gt_length_m) : options.rpe_lengths_m;
  r.rpe = computeRpe(r.est_aligned, r.gt_matched, lengths, options.rpe_length_tolerance);
  std::vector<int64_t> est_t_ns;
  est_t_ns.reserve(r.est_matched.size());
  for (const data::StampedPose& pose : r.est_matched) est_t_ns.push_back(pose.t_ns);
  r.correct_rate = computeCorrectRate(est_t_ns, r.ate.translation_m, r.ate.rotation_deg,
                                      gt.front().t_ns, gt.back().t_ns, options.correct_rate);
  return r;
}

}  // namespace adugs::vio

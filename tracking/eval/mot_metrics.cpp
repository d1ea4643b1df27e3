#include "tracking/eval/mot_metrics.h"

#include <Eigen/Core>
#include <algorithm>
#include <set>

#include "tracking/sort/hungarian.h"

namespace adugs::tracking {

double MotCounts::mota() const {
  return ground_truth > 0
             ? 1.0 - static_cast<double>(false_negatives + false_positives + id_switches) /
                         ground_truth
             : 0.0;
}
double MotCounts::motp() const { return matches > 0 ? iou_sum / matches : 0.0; }
double MotCounts::recall() const {
  return ground_truth > 0 ? static_cast<double>(matches) / ground_truth : 0.0;
}

double MotSummary::precision() const {
  const int hypotheses = counts.matches + counts.false_positives;
  return hypotheses > 0 ? static_cast<double>(counts.matches) / hypotheses : 0.0;
}
double MotSummary::idf1() const {
  const int total = counts.ground_truth + predictions;
  return total > 0 ? 2.0 * idtp / total : 0.0;
}
double MotSummary::idp() const { return predictions > 0 ? static_cast<double>(idtp) / predictions : 0.0; }
double MotSummary::idr() const {
  return counts.ground_truth > 0 ? static_cast<double>(idtp) / counts.ground_truth : 0.0;
}

MotSummary combineMotSummaries(const std::vector<MotSummary>& summaries) {
  MotSummary all;
  for (const MotSummary& s : summaries) {
    all.counts.frames += s.counts.frames;
    all.counts.ground_truth += s.counts.ground_truth;
    all.counts.matches += s.counts.matches;
    all.counts.false_negatives += s.counts.false_negatives;
    all.counts.false_positives += s.counts.false_positives;
    all.counts.id_switches += s.counts.id_switches;
    all.counts.ignored_hypotheses += s.counts.ignored_hypotheses;
    all.counts.iou_sum += s.counts.iou_sum;
    all.unique_objects += s.unique_objects;
    all.mostly_tracked += s.mostly_tracked;
    all.partially_tracked += s.partially_tracked;
    all.mostly_lost += s.mostly_lost;
    all.fragmentations += s.fragmentations;
    all.predictions += s.predictions;
    all.idtp += s.idtp;
  }
  return all;
}

MotSummary MotAccumulator::summary() const {
  MotSummary s;
  s.counts = counts_;
  s.unique_objects = static_cast<int>(gt_matched_.size());
  for (const auto& [id, matched] : gt_matched_) {
    int hits = 0;
    for (bool m : matched) hits += m;
    const double ratio = static_cast<double>(hits) / matched.size();
    if (ratio >= 0.8) ++s.mostly_tracked;
    else if (ratio >= 0.2) ++s.partially_tracked;
    else ++s.mostly_lost;
    // Matched -> missed transitions between the first and the last match.
    size_t first = matched.size(), last = 0;
    for (size_t k = 0; k < matched.size(); ++k)
      if (matched[k]) {
        first = std::min(first, k);
        last = k;
      }
    for (size_t k = first + 1; k <= last && first < matched.size(); ++k)
      if (matched[k - 1] && !matched[k]) ++s.fragmentations;
  }
  for (const auto& [id, frames] : hyp_frames_) s.predictions += frames;

  // Global identity assignment: maximise the overlapping frames of matched trajectory pairs.
  std::map<int64_t, int> gt_row, hyp_col;
  for (const auto& [id, matched] : gt_matched_) gt_row.emplace(id, static_cast<int>(gt_row.size()));
  for (const auto& [id, frames] : hyp_frames_) hyp_col.emplace(id, static_cast<int>(hyp_col.size()));
  if (!gt_row.empty() && !hyp_col.empty()) {
    Eigen::MatrixXd cost = Eigen::MatrixXd::Zero(gt_row.size(), hyp_col.size());
    for (const auto& [pair, frames] : pair_overlaps_) cost(gt_row[pair.first], hyp_col[pair.second]) = -frames;
    const std::vector<int> assignment = solveAssignment(cost);
    for (size_t r = 0; r < assignment.size(); ++r)
      if (assignment[r] >= 0) s.idtp += static_cast<int>(-cost(r, assignment[r]));
  }
  return s;
}

std::vector<bool> MotAccumulator::addFrame(const std::vector<LabelledBox>& gt,
                              const std::vector<LabelledBox>& hyp,
                              const std::vector<Box>& ignored) {
  ++counts_.frames;
  counts_.ground_truth += static_cast<int>(gt.size());
  const int n = static_cast<int>(gt.size()), m = static_cast<int>(hyp.size());
  std::vector<int> hyp_of_gt(n, -1);
  std::vector<bool> hyp_used(m, false);

  // 1. Keep last frame's correspondences that are still good enough.
  for (int i = 0; i < n; ++i) {
    const auto prev = current_match_.find(gt[i].id);
    if (prev == current_match_.end()) continue;
    for (int j = 0; j < m; ++j) {
      if (hyp_used[j] || hyp[j].id != prev->second) continue;
      if (intersectionOverUnion(gt[i].box, hyp[j].box) >= iou_min_) {
        hyp_of_gt[i] = j;
        hyp_used[j] = true;
      }
    }
  }
  // 2. Hungarian on the rest; pairs below iou_min get a cost that is never accepted.
  std::vector<int> free_gt, free_hyp;
  for (int i = 0; i < n; ++i)
    if (hyp_of_gt[i] < 0) free_gt.push_back(i);
  for (int j = 0; j < m; ++j)
    if (!hyp_used[j]) free_hyp.push_back(j);
  Eigen::MatrixXd cost(free_gt.size(), free_hyp.size());
  for (size_t a = 0; a < free_gt.size(); ++a)
    for (size_t b = 0; b < free_hyp.size(); ++b) {
      const double iou = intersectionOverUnion(gt[free_gt[a]].box, hyp[free_hyp[b]].box);
      cost(a, b) = iou >= iou_min_ ? 1.0 - iou : 10.0;
    }
  const std::vector<int> assignment = solveAssignment(cost);
  for (size_t a = 0; a < free_gt.size(); ++a) {
    const int b = assignment[a];
    if (b >= 0 && cost(a, b) <= 1.0) {
      hyp_of_gt[free_gt[a]] = free_hyp[b];
      hyp_used[free_hyp[b]] = true;
    }
  }

  // 3. Count.
  current_match_.clear();
  for (int i = 0; i < n; ++i) {
    const int j = hyp_of_gt[i];
    gt_matched_[gt[i].id].push_back(j >= 0);
    if (j < 0) {
      ++counts_.false_negatives;
      continue;
    }
    ++counts_.matches;
    counts_.iou_sum += intersectionOverUnion(gt[i].box, hyp[j].box);
    const auto last = last_match_.find(gt[i].id);
    if (last != last_match_.end() && last->second != hyp[j].id) {
      ++counts_.id_switches;
      switches_.push_back({counts_.frames, gt[i].id, last->second, hyp[j].id});
    }
    last_match_[gt[i].id] = hyp[j].id;
    current_match_[gt[i].id] = hyp[j].id;
  }
  for (int j = 0; j < m; ++j) {
    if (hyp_used[j]) continue;
    bool on_ignored = false;
    for (const Box& b : ignored)
      on_ignored = on_ignored || intersectionOverUnion(b, hyp[j].box) >= iou_min_;
    if (on_ignored) {
      ++counts_.ignored_hypotheses;
      hyp_used[j] = true;  // not scored: kept out of the identity metrics too
    } else {
      ++counts_.false_positives;
    }
  }
  // Identity metrics: every scored hypothesis, every (gt, hyp) pair overlapping enough.
  std::vector<bool> ignored_hyp(m, false);
  for (int j = 0; j < m; ++j) {
    bool matched = false;
    for (int i = 0; i < n; ++i) matched = matched || hyp_of_gt[i] == j;
    ignored_hyp[j] = hyp_used[j] && !matched;
    if (!ignored_hyp[j]) ++hyp_frames_[hyp[j].id];
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (!ignored_hyp[j] && intersectionOverUnion(gt[i].box, hyp[j].box) >= iou_min_)
        ++pair_overlaps_[{gt[i].id, hyp[j].id}];
  std::vector<bool> scored(m);
  for (int j = 0; j < m; ++j) scored[j] = !ignored_hyp[j];
  return scored;
}

}  // namespace adugs::tracking

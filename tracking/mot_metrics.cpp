#include "tracking/mot_metrics.h"

#include <Eigen/Core>
#include <set>

#include "tracking/hungarian.h"

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

void MotAccumulator::addFrame(const std::vector<LabelledBox>& gt,
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
    if (j < 0) {
      ++counts_.false_negatives;
      continue;
    }
    ++counts_.matches;
    counts_.iou_sum += intersectionOverUnion(gt[i].box, hyp[j].box);
    const auto last = last_match_.find(gt[i].id);
    if (last != last_match_.end() && last->second != hyp[j].id) ++counts_.id_switches;
    last_match_[gt[i].id] = hyp[j].id;
    current_match_[gt[i].id] = hyp[j].id;
  }
  for (int j = 0; j < m; ++j) {
    if (hyp_used[j]) continue;
    bool on_ignored = false;
    for (const Box& b : ignored)
      on_ignored = on_ignored || intersectionOverUnion(b, hyp[j].box) >= iou_min_;
    if (on_ignored)
      ++counts_.ignored_hypotheses;
    else
      ++counts_.false_positives;
  }
}

}  // namespace adugs::tracking

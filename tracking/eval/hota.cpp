#include "tracking/eval/hota.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tracking/sort/hungarian.h"

namespace adugs::tracking {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

template <typename F>
double meanOverAlphas(F per_alpha) {
  double sum = 0;
  for (int a = 0; a < kHotaAlphas; ++a) sum += per_alpha(a);
  return sum / kHotaAlphas;
}

}  // namespace

double hotaAlpha(int a) { return 0.05 * (a + 1); }

double HotaSummary::detA(int a) const { return tp[a] / std::max(1.0, tp[a] + fn[a] + fp[a]); }
double HotaSummary::detRe(int a) const { return tp[a] / std::max(1.0, tp[a] + fn[a]); }
double HotaSummary::detPr(int a) const { return tp[a] / std::max(1.0, tp[a] + fp[a]); }
double HotaSummary::hota(int a) const { return std::sqrt(detA(a) * ass_a[a]); }
double HotaSummary::hota() const { return meanOverAlphas([&](int a) { return hota(a); }); }
double HotaSummary::detA() const { return meanOverAlphas([&](int a) { return detA(a); }); }
double HotaSummary::assA() const { return meanOverAlphas([&](int a) { return ass_a[a]; }); }
double HotaSummary::detRe() const { return meanOverAlphas([&](int a) { return detRe(a); }); }
double HotaSummary::detPr() const { return meanOverAlphas([&](int a) { return detPr(a); }); }
double HotaSummary::assRe() const { return meanOverAlphas([&](int a) { return ass_re[a]; }); }
double HotaSummary::assPr() const { return meanOverAlphas([&](int a) { return ass_pr[a]; }); }
double HotaSummary::locA() const { return meanOverAlphas([&](int a) { return loc_a[a]; }); }

HotaSummary combineHotaSummaries(const std::vector<HotaSummary>& summaries) {
  HotaSummary all;
  for (int a = 0; a < kHotaAlphas; ++a) {
    double ass_a = 0, ass_re = 0, ass_pr = 0, loc_a = 0;
    for (const HotaSummary& s : summaries) {
      all.tp[a] += s.tp[a];
      all.fn[a] += s.fn[a];
      all.fp[a] += s.fp[a];
      ass_a += s.ass_a[a] * s.tp[a];
      ass_re += s.ass_re[a] * s.tp[a];
      ass_pr += s.ass_pr[a] * s.tp[a];
      loc_a += s.loc_a[a] * s.tp[a];
    }
    all.ass_a[a] = ass_a / std::max(1.0, all.tp[a]);
    all.ass_re[a] = ass_re / std::max(1.0, all.tp[a]);
    all.ass_pr[a] = ass_pr / std::max(1.0, all.tp[a]);
    all.loc_a[a] = std::max(1e-10, loc_a) / std::max(1e-10, all.tp[a]);
  }
  return all;
}

int HotaAccumulator::index(std::map<int64_t, int>& ids, int64_t id) {
  return ids.emplace(id, static_cast<int>(ids.size())).first->second;
}

void HotaAccumulator::addFrame(const std::vector<LabelledBox>& ground_truth,
                               const std::vector<LabelledBox>& hypotheses) {
  Frame f;
  for (const LabelledBox& g : ground_truth) f.gt.push_back(index(gt_ids_, g.id));
  for (const LabelledBox& h : hypotheses) f.hyp.push_back(index(hyp_ids_, h.id));
  for (const LabelledBox& g : ground_truth)
    for (const LabelledBox& h : hypotheses) f.iou.push_back(intersectionOverUnion(g.box, h.box));
  frames_.push_back(std::move(f));
}

HotaSummary HotaAccumulator::summary() const {
  HotaSummary s;
  const int n_gt_ids = static_cast<int>(gt_ids_.size()), n_hyp_ids = static_cast<int>(hyp_ids_.size());
  int gt_boxes = 0, hyp_boxes = 0;
  for (const Frame& f : frames_) {
    gt_boxes += static_cast<int>(f.gt.size());
    hyp_boxes += static_cast<int>(f.hyp.size());
  }
  if (hyp_boxes == 0 || gt_boxes == 0) {  // as TrackEval: everything missed / false, LocA 1
    for (int a = 0; a < kHotaAlphas; ++a) {
      s.fn[a] = gt_boxes;
      s.fp[a] = hyp_boxes;
      s.loc_a[a] = 1.0;
    }
    return s;
  }

  // 1. Global alignment of every id pair.
  Eigen::MatrixXd potential = Eigen::MatrixXd::Zero(n_gt_ids, n_hyp_ids);
  Eigen::VectorXd gt_count = Eigen::VectorXd::Zero(n_gt_ids), hyp_count = Eigen::VectorXd::Zero(n_hyp_ids);
  for (const Frame& f : frames_) {
    const int n = static_cast<int>(f.gt.size()), m = static_cast<int>(f.hyp.size());
    std::vector<double> row_sum(n, 0.0), col_sum(m, 0.0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        row_sum[i] += f.iou[i * m + j];
        col_sum[j] += f.iou[i * m + j];
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        const double sim = f.iou[i * m + j], denom = row_sum[i] + col_sum[j] - sim;
        if (denom > kEps) potential(f.gt[i], f.hyp[j]) += sim / denom;
      }
    for (int g : f.gt) gt_count(g) += 1;
    for (int h : f.hyp) hyp_count(h) += 1;
  }
  Eigen::MatrixXd alignment(n_gt_ids, n_hyp_ids);
  for (int g = 0; g < n_gt_ids; ++g)
    for (int h = 0; h < n_hyp_ids; ++h)
      alignment(g, h) = potential(g, h) / (gt_count(g) + hyp_count(h) - potential(g, h));

  // 2. Per frame: the matching that maximises alignment x IoU, counted per alpha.
  std::vector<std::map<std::pair<int, int>, int>> matches(kHotaAlphas);  // (g, h) -> TP frames
  for (const Frame& f : frames_) {
    const int n = static_cast<int>(f.gt.size()), m = static_cast<int>(f.hyp.size());
    if (n == 0 || m == 0) {
      for (int a = 0; a < kHotaAlphas; ++a) {
        s.fp[a] += m;
        s.fn[a] += n;
      }
      continue;
    }
    Eigen::MatrixXd cost(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) cost(i, j) = -alignment(f.gt[i], f.hyp[j]) * f.iou[i * m + j];
    const std::vector<int> assignment = solveAssignment(cost);
    for (int a = 0; a < kHotaAlphas; ++a) {
      int tp = 0;
      for (int i = 0; i < n; ++i) {
        const int j = assignment[i];
        if (j < 0 || f.iou[i * m + j] < hotaAlpha(a) - kEps) continue;
        ++tp;
        s.loc_a[a] += f.iou[i * m + j];
        ++matches[a][{f.gt[i], f.hyp[j]}];
      }
      s.tp[a] += tp;
      s.fn[a] += n - tp;
      s.fp[a] += m - tp;
    }
  }

  // 3. Association accuracy of the matched pairs, averaged over the true positives.
  for (int a = 0; a < kHotaAlphas; ++a) {
    double ass_a = 0, ass_re = 0, ass_pr = 0;
    for (const auto& [pair, c] : matches[a]) {
      const double n_g = gt_count(pair.first), n_h = hyp_count(pair.second);
      ass_a += c * (c / std::max(1.0, n_g + n_h - c));
      ass_re += c * (c / std::max(1.0, n_g));
      ass_pr += c * (c / std::max(1.0, n_h));
    }
    s.ass_a[a] = ass_a / std::max(1.0, s.tp[a]);
    s.ass_re[a] = ass_re / std::max(1.0, s.tp[a]);
    s.ass_pr[a] = ass_pr / std::max(1.0, s.tp[a]);
    s.loc_a[a] = std::max(1e-10, s.loc_a[a]) / std::max(1e-10, s.tp[a]);
  }
  return s;
}

}  // namespace adugs::tracking

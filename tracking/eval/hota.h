#pragma once
// HOTA, Higher Order Tracking Accuracy (Luiten et al., IJCV 2021), computed as TrackEval does.
// For each localisation threshold alpha in 0.05, 0.10, ..., 0.95:
//   1. Over the whole sequence, every (gt id, hypothesis id) pair gets a global alignment score
//        A(g, h) = P(g, h) / (n_g + n_h - P(g, h)),
//      n_g, n_h = frames where g / h is present, P(g, h) = sum over frames of S / (S_row + S_col - S)
//      (S = IoU of the two boxes, S_row / S_col = the sums of IoU over g's row / h's column).
//   2. Per frame, the Hungarian algorithm maximises A(g, h) * S(g, h); matched pairs with
//      S >= alpha are true positives (TP), the other gt boxes misses (FN), the other hypothesis
//      boxes false positives (FP).
//   3. DetA = TP / (TP + FN + FP); per matched pair the association accuracy
//        c(g, h) / (n_g + n_h - c(g, h)), c = frames where g and h are TP-matched,
//      averaged over all TPs (AssA); AssRe, AssPr likewise with n_g, n_h alone;
//      HOTA = sqrt(DetA * AssA); LocA = mean IoU of the TPs.
// The reported HOTA, DetA, AssA, LocA... are the means over the 19 alphas.
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "tracking/eval/mot_metrics.h"

namespace adugs::tracking {

constexpr int kHotaAlphas = 19;  // alpha = 0.05 (a + 1), a = 0..18
double hotaAlpha(int a);

struct HotaSummary {
  std::array<double, kHotaAlphas> tp{}, fn{}, fp{};
  std::array<double, kHotaAlphas> ass_a{}, ass_re{}, ass_pr{}, loc_a{};
  // Per alpha.
  double detA(int a) const;
  double detRe(int a) const;
  double detPr(int a) const;
  double hota(int a) const;
  // Means over the alphas (what TrackEval reports).
  double hota() const;
  double detA() const;
  double assA() const;
  double detRe() const;
  double detPr() const;
  double assRe() const;
  double assPr() const;
  double locA() const;
};

// Several sequences as one (TrackEval's COMBINED_SEQ): TP, FN, FP summed; AssA, AssRe, AssPr and
// LocA averaged weighted by TP, per alpha.
HotaSummary combineHotaSummaries(const std::vector<HotaSummary>& summaries);

// Collects the frames of one sequence; the global alignment needs all of them before scoring.
class HotaAccumulator {
 public:
  void addFrame(const std::vector<LabelledBox>& ground_truth, const std::vector<LabelledBox>& hypotheses);
  HotaSummary summary() const;

 private:
  struct Frame {
    std::vector<int> gt, hyp;       // contiguous ids
    std::vector<double> iou;        // gt.size() x hyp.size(), row major
  };
  int index(std::map<int64_t, int>& ids, int64_t id);
  std::vector<Frame> frames_;
  std::map<int64_t, int> gt_ids_, hyp_ids_;
};

}  // namespace adugs::tracking

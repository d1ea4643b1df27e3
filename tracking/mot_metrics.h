#pragma once
// CLEAR-MOT metrics (Bernardin & Stiefelhagen 2008), as MOTChallenge computes them:
// per frame, ground-truth objects are matched to hypotheses with IoU >= iou_min. A correspondence
// from the previous frame is kept while it still has IoU >= iou_min; the rest are matched by
// the Hungarian algorithm on 1 - IoU. A ground-truth object whose matched hypothesis id differs
// from its last matched id counts as an identity switch.
//   MOTA = 1 - (FN + FP + IDSW) / GT,   MOTP = mean IoU of the matches.
#include <cstdint>
#include <map>
#include <vector>

#include "tracking/box.h"

namespace adugs::tracking {

struct LabelledBox {
  int64_t id = 0;
  Box box;
};

struct MotCounts {
  int frames = 0;
  int ground_truth = 0;  // GT boxes over all frames
  int matches = 0;
  int false_negatives = 0;
  int false_positives = 0;
  int id_switches = 0;
  int ignored_hypotheses = 0;  // unmatched hypotheses on ignored regions (not counted as FP)
  double iou_sum = 0;
  double mota() const;
  double motp() const;    // mean IoU of matches (1 = perfect)
  double recall() const;  // matches / ground_truth
};

class MotAccumulator {
 public:
  explicit MotAccumulator(double iou_min = 0.5) : iou_min_(iou_min) {}
  // ignored: ground-truth regions not scored (e.g. objects hidden beyond a visibility threshold,
  // as MOTChallenge treats occluded people): an unmatched hypothesis on one of them is neither a
  // match nor a false positive.
  void addFrame(const std::vector<LabelledBox>& ground_truth,
                const std::vector<LabelledBox>& hypotheses, const std::vector<Box>& ignored = {});
  const MotCounts& counts() const { return counts_; }

 private:
  double iou_min_;
  MotCounts counts_;
  std::map<int64_t, int64_t> current_match_;  // gt id -> hypothesis id matched last frame
  std::map<int64_t, int64_t> last_match_;     // gt id -> hypothesis id matched most recently
};

}  // namespace adugs::tracking

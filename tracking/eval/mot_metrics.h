#pragma once
// CLEAR-MOT metrics (Bernardin & Stiefelhagen 2008), as MOTChallenge computes them:
// per frame, ground-truth objects are matched to hypotheses with IoU >= iou_min. A correspondence
// from the previous frame is kept while it still has IoU >= iou_min; the rest are matched by
// the Hungarian algorithm on 1 - IoU. A ground-truth object whose matched hypothesis id differs
// from its last matched id counts as an identity switch.
//   MOTA = 1 - (FN + FP + IDSW) / GT,   MOTP = mean IoU of the matches.
// The summary adds, with py-motmetrics' definitions (its MOTChallenge test values reproduce):
//   MT / PT / ML: ground-truth objects matched in >= 80 %, 20-80 %, < 20 % of their frames;
//   fragmentations: per object, changes from matched to missed between its first and last match;
//   identity metrics (Ristani et al. 2016): one global one-to-one assignment of ground-truth
//   trajectories to hypothesis trajectories maximising the frames where the pair overlaps with
//   IoU >= iou_min (IDTP); IDP = IDTP / predictions, IDR = IDTP / GT, IDF1 = 2 IDTP / (GT + predictions).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "tracking/box.h"

namespace adugs::tracking {

struct LabelledBox {
  int64_t id = 0;
  Box box;
};

// A ground-truth object matched to another hypothesis than the one it was last matched to.
struct IdSwitch {
  int frame = 0;  // index of the addFrame() call, from 1
  int64_t gt_id = 0, previous_hypothesis = 0, hypothesis = 0;
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

struct MotSummary {
  MotCounts counts;
  int unique_objects = 0;
  int mostly_tracked = 0, partially_tracked = 0, mostly_lost = 0;
  int fragmentations = 0;
  int predictions = 0;  // hypothesis boxes scored (those on ignored regions are not)
  int idtp = 0;         // identity true positives
  double mota() const { return counts.mota(); }
  double motpIou() const { return counts.motp(); }              // mean IoU of matches
  double motpDistance() const { return 1.0 - counts.motp(); }   // py-motmetrics' motp (1 - IoU)
  double recall() const { return counts.recall(); }
  double precision() const;
  double idf1() const;
  double idp() const;
  double idr() const;
};

// Several sequences as one (MOTChallenge's OVERALL row): counts summed, ratios recomputed.
MotSummary combineMotSummaries(const std::vector<MotSummary>& summaries);

class MotAccumulator {
 public:
  explicit MotAccumulator(double iou_min = 0.5) : iou_min_(iou_min) {}
  // ignored: ground-truth regions not scored (e.g. objects hidden beyond a visibility threshold,
  // as MOTChallenge treats occluded people): an unmatched hypothesis on one of them is neither a
  // match nor a false positive. Returns, per hypothesis, whether it was scored (false: it sits on
  // an ignored region), so that other metrics (HOTA) can leave out the same boxes.
  std::vector<bool> addFrame(const std::vector<LabelledBox>& ground_truth,
                const std::vector<LabelledBox>& hypotheses, const std::vector<Box>& ignored = {});
  const MotCounts& counts() const { return counts_; }
  const std::vector<IdSwitch>& idSwitches() const { return switches_; }
  MotSummary summary() const;

 private:
  double iou_min_;
  MotCounts counts_;
  std::vector<IdSwitch> switches_;
  std::map<int64_t, int64_t> current_match_;  // gt id -> hypothesis id matched last frame
  std::map<int64_t, int64_t> last_match_;     // gt id -> hypothesis id matched most recently
  std::map<int64_t, std::vector<bool>> gt_matched_;  // gt id -> matched or not, per frame present
  std::map<int64_t, int> hyp_frames_;                // hypothesis id -> frames scored
  std::map<std::pair<int64_t, int64_t>, int> pair_overlaps_;  // (gt, hyp) -> frames IoU >= iou_min
};

}  // namespace adugs::tracking

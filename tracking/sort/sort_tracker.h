#pragma once
// Enhanced SORT (doc/architecture.md, "The method"): per frame, every track's adaptive Kalman
// filter predicts its box; the Hungarian algorithm matches predictions to detections on 1 - IoU
// (same class only); matches with IoU below iou_min are refused. Matched tracks fuse their
// detection, unmatched detections start tracks, unmatched tracks coast on their prediction for up
// to max_age frames - the predicted box stands in for a missed detection (partial or full
// occlusion) so the dynamic mask keeps covering the object. Optional association stages after the
// first (ByteTrack's low-score detections, OC-SORT's last-box recovery) and cost terms (appearance,
// OC-SORT's direction momentum): SortOptions and doc/tracking.md.
#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/box.h"
#include "tracking/detect/detector.h"
#include "tracking/sort/adaptive_box_filter.h"

namespace adugs::tracking {

struct TrackedObject {
  int64_t id = 0;  // persistent, never reused
  Box box;         // filtered (detected) or predicted (coasting) box
  int class_id = 0;
  bool detected = false;  // matched to a detection this frame
  int hits = 0;           // detections fused so far
  int frames_missed = 0;  // consecutive frames without a detection
};

struct SortOptions {
  double iou_min = 0.3;
  int max_age = 5;   // frames a track coasts without detections before it is deleted
  int min_hits = 2;  // detections before a track is reported (reported at once while the
                     // tracker itself is younger than min_hits frames, as SORT does)
  AdaptiveNoiseOptions filter;
  // OC-SORT's observation-centric re-update: when a track is found again after coasting k frames,
  // its filter goes back to the state after its last detection and fuses k virtual detections on
  // the straight line from that detection to the new one, then the new one. The coasting
  // prediction's velocity error (which grows during an occlusion) is not kept.
  bool observation_centric_recovery = false;  // no measured gain yet (doc/results.md)
  // Appearance cue: association cost (1 - IoU) + appearance_weight (1 - Bhattacharyya coefficient)
  // between the detection's histogram and the track's (an exponential average, new = 0.2); pairs
  // still need IoU >= iou_min. 0 = off.
  double appearance_weight = 0.0;

  // --- Association stages (doc/tracking.md "Association"); each off by default. ---
  // ByteTrack's two stages: detections scoring below high_score never start a track and are only
  // offered, after the first association, to the tracks that were found in the previous frame and
  // are still unmatched (IoU >= low_iou_min). 0 = every detection is a high one.
  double high_score = 0.0;
  double low_iou_min = 0.5;
  // OC-SORT's observation-centric recovery (OCR): tracks still unmatched after the first stage(s)
  // are matched to the remaining detections by the IoU of their LAST DETECTED box instead of
  // their prediction (a coasting prediction drifts; a person who stopped behind someone is where
  // they were last seen).
  bool last_box_association = false;
  // OC-SORT's observation-centric momentum (OCM): the cost of a pair gets
  //   - direction_weight * score * (pi/2 - angle) / pi,
  // angle = between the track's direction of motion (its last detection minus the one
  // direction_frames earlier) and the direction from that earlier detection to the candidate:
  // a detection continuing the track's motion costs less than one behind it. 0 = off.
  double direction_weight = 0.0;
  int direction_frames = 3;
  // A track that has not yet reached min_hits is deleted at its first missed frame (DeepSORT's
  // tentative tracks): one-off false detections do not coast and steal later detections.
  bool drop_unconfirmed_on_miss = false;
  // A coasting track is reported (update's and predict's output) at most this many times the
  // width and height it had when last detected: the filter keeps the size velocity of its last
  // frames, and without detections a box swelled from 91 x 277 to 165 x 566 px in four frames
  // over vtest.avi's parked van. The filter itself is not capped (association is unchanged).
  // 0 = no cap. (With camera-motion compensation the last detected size is warped as the image.)
  double coasting_growth_max = 1.2;
};

class SortTracker {
 public:
  explicit SortTracker(const SortOptions& options = {});

  // One frame: detections in, the confirmed tracks out (detected or coasting).
  // dt: frames since the previous call (1 for consecutive frames).
  std::vector<TrackedObject> update(const std::vector<Detection>& detections, double dt = 1.0);

  // Camera-motion compensation before the next update()/predict(): every track's filter is moved
  // as the image moved since the previous frame (`map`: previous-image pixel -> current-image
  // pixel, e.g. from the gyro), so association and coasting see only the objects' own motion.
  void compensateCameraMotion(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map);

  // The tracks the last update() reported, their boxes predicted dt frames past it, the state
  // unchanged: what carries the boxes across frames the detector skips (marked not detected).
  std::vector<TrackedObject> predict(double dt) const;

  int liveTracks() const { return static_cast<int>(tracks_.size()); }

 private:
  struct Observation {
    double time = 0;  // tracker time (sum of dt) of the detection
    Box box;
  };
  struct Track {
    TrackedObject object;
    AdaptiveBoxFilter filter;
    AdaptiveBoxFilter filter_at_last_detection;  // for the observation-centric re-update
    Box last_detection;
    double dt_since_detection = 0;
    cv::Mat appearance;                    // averaged boxHistogram, empty without
    std::deque<Observation> observations;  // the last direction_frames + 1 detections
  };
  // Cost of associating a track with a detection, or a value > 1 + appearance when not allowed.
  double associationCost(const Track& track, const Detection& detection, double iou) const;
  void match(const std::vector<int>& track_ids, const std::vector<int>& detection_ids,
             const std::vector<Detection>& detections, bool by_last_box, double iou_min,
             std::vector<int>* detection_of_track, std::vector<bool>* detection_used) const;
  void fuse(Track& track, const Detection& detection);
  bool reported(const Track& track) const;
  Box capGrowth(const Track& track, Box box) const;  // coasting_growth_max
  SortOptions options_;
  std::vector<Track> tracks_;
  int64_t next_id_ = 1;
  int frames_ = 0;
  double time_ = 0;
};

}  // namespace adugs::tracking

#pragma once
// Enhanced SORT (DESIGN.md): per frame, every track's adaptive Kalman filter predicts its box;
// the Hungarian algorithm matches predictions to detections on 1 - IoU (same class only);
// matches with IoU below iou_min are refused. Matched tracks fuse their detection, unmatched
// detections start tracks, unmatched tracks coast on their prediction for up to max_age frames -
// the predicted box stands in for a missed detection (partial or full occlusion) so the dynamic
// mask keeps covering the object.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/adaptive_box_filter.h"
#include "tracking/box.h"

namespace adugs::tracking {

struct Detection {
  Box box;
  int class_id = 0;
  double score = 1.0;
  cv::Mat appearance = cv::Mat();  // optional boxHistogram (tracking/appearance.h); used when appearance_weight > 0
};

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
  struct Track {
    TrackedObject object;
    AdaptiveBoxFilter filter;
    AdaptiveBoxFilter filter_at_last_detection;  // for the observation-centric re-update
    Box last_detection;
    double dt_since_detection = 0;
    cv::Mat appearance;  // averaged boxHistogram, empty without
  };
  void fuse(Track& track, const Box& detection);
  bool reported(const Track& track) const;
  SortOptions options_;
  std::vector<Track> tracks_;
  int64_t next_id_ = 1;
  int frames_ = 0;
};

}  // namespace adugs::tracking

#include "tracking/sort_tracker.h"

#include <algorithm>

#include "tracking/hungarian.h"

namespace adugs::tracking {

SortTracker::SortTracker(const SortOptions& options) : options_(options) {}

std::vector<TrackedObject> SortTracker::update(const std::vector<Detection>& detections,
                                               double dt) {
  ++frames_;
  for (Track& t : tracks_) t.object.box = t.filter.predict(dt);

  // Cost 1 - IoU; pairs of different classes can never match (cost above any accepted pair).
  const int n_tracks = static_cast<int>(tracks_.size());
  const int n_dets = static_cast<int>(detections.size());
  Eigen::MatrixXd cost(n_tracks, n_dets);
  for (int i = 0; i < n_tracks; ++i)
    for (int j = 0; j < n_dets; ++j)
      cost(i, j) = tracks_[i].object.class_id == detections[j].class_id
                       ? 1.0 - intersectionOverUnion(tracks_[i].object.box, detections[j].box)
                       : 2.0;
  const std::vector<int> match = solveAssignment(cost);

  std::vector<bool> detection_used(n_dets, false);
  for (int i = 0; i < n_tracks; ++i) {
    TrackedObject& o = tracks_[i].object;
    const int j = match[i];
    if (j >= 0 && 1.0 - cost(i, j) >= options_.iou_min) {
      tracks_[i].filter.update(detections[j].box);
      o.box = tracks_[i].filter.box();
      o.detected = true;
      ++o.hits;
      o.frames_missed = 0;
      detection_used[j] = true;
    } else {
      o.detected = false;
      ++o.frames_missed;
    }
  }
  tracks_.erase(
      std::remove_if(tracks_.begin(), tracks_.end(),
                     [&](const Track& t) { return t.object.frames_missed > options_.max_age; }),
      tracks_.end());
  for (int j = 0; j < n_dets; ++j) {
    if (detection_used[j]) continue;
    TrackedObject o;
    o.id = next_id_++;
    o.box = detections[j].box;
    o.class_id = detections[j].class_id;
    o.detected = true;
    o.hits = 1;
    tracks_.push_back({o, AdaptiveBoxFilter(detections[j].box, options_.filter)});
  }

  std::vector<TrackedObject> out;
  for (const Track& t : tracks_)
    if (t.object.hits >= options_.min_hits || frames_ <= options_.min_hits) out.push_back(t.object);
  return out;
}

}  // namespace adugs::tracking

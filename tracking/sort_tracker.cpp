#include "tracking/sort_tracker.h"

#include <algorithm>

#include "tracking/appearance.h"
#include "tracking/hungarian.h"

namespace adugs::tracking {

SortTracker::SortTracker(const SortOptions& options) : options_(options) {}

void SortTracker::fuse(Track& t, const Box& detection) {
  const int missed = t.object.frames_missed;
  if (options_.observation_centric_recovery && missed > 0) {
    t.filter = t.filter_at_last_detection;
    const Box& a = t.last_detection;
    const double step = t.dt_since_detection / (missed + 1);  // frames between the virtual ones
    for (int k = 1; k <= missed; ++k) {
      const double s = static_cast<double>(k) / (missed + 1);
      t.filter.predict(step);
      t.filter.update(Box{a.cx + s * (detection.cx - a.cx), a.cy + s * (detection.cy - a.cy),
                          a.w + s * (detection.w - a.w), a.h + s * (detection.h - a.h)});
    }
    t.filter.predict(step);
  }
  t.filter.update(detection);
  t.dt_since_detection = 0;
  t.filter_at_last_detection = t.filter;
  t.last_detection = detection;
}

std::vector<TrackedObject> SortTracker::update(const std::vector<Detection>& detections,
                                               double dt) {
  ++frames_;
  for (Track& t : tracks_) {
    t.object.box = t.filter.predict(dt);
    t.dt_since_detection += dt;
  }

  // Cost 1 - IoU (+ the appearance term); pairs of different classes can never match (cost above
  // any accepted pair). The IoU gate is checked on the IoU alone.
  const int n_tracks = static_cast<int>(tracks_.size());
  const int n_dets = static_cast<int>(detections.size());
  const double w = options_.appearance_weight;
  Eigen::MatrixXd iou(n_tracks, n_dets), cost(n_tracks, n_dets);
  for (int i = 0; i < n_tracks; ++i)
    for (int j = 0; j < n_dets; ++j) {
      iou(i, j) = intersectionOverUnion(tracks_[i].object.box, detections[j].box);
      const bool same_class = tracks_[i].object.class_id == detections[j].class_id;
      double appearance = 0;
      if (w > 0 && !tracks_[i].appearance.empty() && !detections[j].appearance.empty())
        appearance = w * (1.0 - histogramSimilarity(tracks_[i].appearance, detections[j].appearance));
      cost(i, j) = same_class ? 1.0 - iou(i, j) + appearance : 2.0 + w;
    }
  const std::vector<int> match = solveAssignment(cost);

  std::vector<bool> detection_used(n_dets, false);
  for (int i = 0; i < n_tracks; ++i) {
    TrackedObject& o = tracks_[i].object;
    const int j = match[i];
    if (j >= 0 && o.class_id == detections[j].class_id && iou(i, j) >= options_.iou_min) {
      fuse(tracks_[i], detections[j].box);
      if (!detections[j].appearance.empty())
        tracks_[i].appearance = tracks_[i].appearance.empty()
                                    ? detections[j].appearance.clone()
                                    : cv::Mat(0.8 * tracks_[i].appearance + 0.2 * detections[j].appearance);
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
    const AdaptiveBoxFilter filter(detections[j].box, options_.filter);
    tracks_.push_back({o, filter, filter, detections[j].box, 0.0, detections[j].appearance.clone()});
  }

  std::vector<TrackedObject> out;
  for (const Track& t : tracks_)
    if (reported(t)) out.push_back(t.object);
  return out;
}

bool SortTracker::reported(const Track& t) const {
  return t.object.hits >= options_.min_hits || frames_ <= options_.min_hits;
}

void SortTracker::compensateCameraMotion(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map) {
  for (Track& t : tracks_) {
    t.filter.warp(map);
    t.filter_at_last_detection.warp(map);
    const Eigen::Vector2d c = map({t.last_detection.cx, t.last_detection.cy});
    t.last_detection.cx = c.x();
    t.last_detection.cy = c.y();
  }
}

std::vector<TrackedObject> SortTracker::predict(double dt) const {
  std::vector<TrackedObject> out;
  for (const Track& t : tracks_) {
    if (!reported(t)) continue;
    AdaptiveBoxFilter filter = t.filter;
    TrackedObject o = t.object;
    o.box = filter.predict(dt);
    o.detected = false;
    out.push_back(o);
  }
  return out;
}

}  // namespace adugs::tracking

#include "tracking/sort/sort_tracker.h"

#include <algorithm>
#include <cmath>

#include "tracking/sort/appearance.h"
#include "tracking/sort/hungarian.h"

namespace adugs::tracking {

SortTracker::SortTracker(const SortOptions& options) : options_(options) {}

void SortTracker::fuse(Track& t, const Detection& d) {
  const Box& detection = d.box;
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
  t.observations.push_back({time_, detection});
  while (static_cast<int>(t.observations.size()) > std::max(1, options_.direction_frames) + 1)
    t.observations.pop_front();
  if (!d.appearance.empty())
    t.appearance = t.appearance.empty() ? d.appearance.clone() : cv::Mat(0.8 * t.appearance + 0.2 * d.appearance);
  TrackedObject& o = t.object;
  o.box = t.filter.box();
  o.detected = true;
  ++o.hits;
  o.frames_missed = 0;
}

double SortTracker::associationCost(const Track& t, const Detection& d, double iou) const {
  double cost = 1.0 - iou;
  const double w = options_.appearance_weight;
  if (w > 0 && !t.appearance.empty() && !d.appearance.empty())
    cost += w * (1.0 - histogramSimilarity(t.appearance, d.appearance));
  if (options_.direction_weight > 0 && t.observations.size() >= 2) {
    // Directions from the oldest kept detection: to the newest (the track's motion) and to the
    // candidate. Parallel: bonus w * score / 2; perpendicular: 0; opposite: penalty w * score / 2.
    const Box& from = t.observations.front().box;
    const Box& to = t.observations.back().box;
    const Eigen::Vector2d track_dir(to.cx - from.cx, to.cy - from.cy);
    const Eigen::Vector2d candidate_dir(d.box.cx - from.cx, d.box.cy - from.cy);
    if (track_dir.norm() > 1e-6 && candidate_dir.norm() > 1e-6) {
      const double c = std::clamp(track_dir.normalized().dot(candidate_dir.normalized()), -1.0, 1.0);
      cost -= options_.direction_weight * d.score * (M_PI / 2 - std::acos(c)) / M_PI;
    }
  }
  return cost;
}

void SortTracker::match(const std::vector<int>& track_ids, const std::vector<int>& detection_ids,
                        const std::vector<Detection>& detections, bool by_last_box, double iou_min,
                        std::vector<int>* detection_of_track, std::vector<bool>* detection_used) const {
  if (track_ids.empty() || detection_ids.empty()) return;
  // As SORT: the assignment minimises the cost over all pairs of the same class, then pairs below
  // the IoU gate are refused (gating before the assignment measured slightly worse on TUD-Campus).
  constexpr double kOtherClass = 1e3;  // above any cost of a same-class pair
  Eigen::MatrixXd cost(track_ids.size(), detection_ids.size()), iou(track_ids.size(), detection_ids.size());
  for (size_t a = 0; a < track_ids.size(); ++a)
    for (size_t b = 0; b < detection_ids.size(); ++b) {
      const Track& t = tracks_[track_ids[a]];
      const Detection& d = detections[detection_ids[b]];
      iou(a, b) = intersectionOverUnion(by_last_box ? t.last_detection : t.object.box, d.box);
      cost(a, b) = t.object.class_id == d.class_id ? associationCost(t, d, iou(a, b)) : kOtherClass;
    }
  const std::vector<int> assignment = solveAssignment(cost);
  for (size_t a = 0; a < track_ids.size(); ++a) {
    const int b = assignment[a];
    if (b < 0 || cost(a, b) >= kOtherClass || iou(a, b) < iou_min) continue;
    (*detection_of_track)[track_ids[a]] = detection_ids[b];
    (*detection_used)[detection_ids[b]] = true;
  }
}

std::vector<TrackedObject> SortTracker::update(const std::vector<Detection>& detections,
                                               double dt) {
  ++frames_;
  time_ += dt;
  std::vector<bool> found_last_frame(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    found_last_frame[i] = t.object.frames_missed == 0;
    t.object.box = t.filter.predict(dt);
    t.dt_since_detection += dt;
  }

  const int n_tracks = static_cast<int>(tracks_.size());
  const int n_dets = static_cast<int>(detections.size());
  std::vector<int> detection_of_track(n_tracks, -1);
  std::vector<bool> detection_used(n_dets, false);
  const auto unmatched_tracks = [&](bool only_found_last_frame) {
    std::vector<int> ids;
    for (int i = 0; i < n_tracks; ++i)
      if (detection_of_track[i] < 0 && (!only_found_last_frame || found_last_frame[i])) ids.push_back(i);
    return ids;
  };
  const auto unused_detections = [&](bool high) {
    std::vector<int> ids;
    for (int j = 0; j < n_dets; ++j)
      if (!detection_used[j] && (detections[j].score >= options_.high_score) == high) ids.push_back(j);
    return ids;
  };
  // 1. Every track's prediction against the confident detections.
  match(unmatched_tracks(false), unused_detections(true), detections, false, options_.iou_min,
        &detection_of_track, &detection_used);
  // 2. ByteTrack: tracks found last frame and still unmatched take the low-score detections.
  if (options_.high_score > 0)
    match(unmatched_tracks(true), unused_detections(false), detections, false, options_.low_iou_min,
          &detection_of_track, &detection_used);
  // 3. OC-SORT's recovery: the remaining tracks by their last detected box.
  if (options_.last_box_association)
    match(unmatched_tracks(false), unused_detections(true), detections, true, options_.iou_min,
          &detection_of_track, &detection_used);

  for (int i = 0; i < n_tracks; ++i) {
    if (detection_of_track[i] >= 0) {
      fuse(tracks_[i], detections[detection_of_track[i]]);
    } else {
      tracks_[i].object.detected = false;
      ++tracks_[i].object.frames_missed;
    }
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) {
                                 const bool unconfirmed_lost = options_.drop_unconfirmed_on_miss &&
                                                               t.object.frames_missed > 0 &&
                                                               t.object.hits < options_.min_hits;
                                 return t.object.frames_missed > options_.max_age || unconfirmed_lost;
                               }),
                tracks_.end());
  for (int j = 0; j < n_dets; ++j) {
    if (detection_used[j] || detections[j].score < options_.high_score) continue;
    TrackedObject o;
    o.id = next_id_++;
    o.box = detections[j].box;
    o.class_id = detections[j].class_id;
    o.detected = true;
    o.hits = 1;
    const AdaptiveBoxFilter filter(detections[j].box, options_.filter);
    Track t{o, filter, filter, detections[j].box, 0.0, detections[j].appearance.clone(), {}};
    t.observations.push_back({time_, detections[j].box});
    tracks_.push_back(std::move(t));
  }

  std::vector<TrackedObject> out;
  for (const Track& t : tracks_) {
    if (!reported(t)) continue;
    out.push_back(t.object);
    if (t.object.frames_missed > 0) out.back().box = capGrowth(t, t.object.box);
  }
  return out;
}

Box SortTracker::capGrowth(const Track& t, Box box) const {
  if (options_.coasting_growth_max <= 0) return box;
  const Box seen = t.filter_at_last_detection.box();  // the box reported when last detected
  box.w = std::min(box.w, options_.coasting_growth_max * seen.w);
  box.h = std::min(box.h, options_.coasting_growth_max * seen.h);
  return box;
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
    o.box = capGrowth(t, filter.predict(dt));
    o.detected = false;
    out.push_back(o);
  }
  return out;
}

}  // namespace adugs::tracking

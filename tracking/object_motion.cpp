#include "tracking/object_motion.h"

#include <algorithm>
#include <cmath>

namespace adugs::tracking {

void ObjectMotionClassifier::update(const std::vector<TrackedObject>& objects, const std::vector<MotionCuePoint>& points,
                                    bool translating) {
  std::map<int64_t, State> next;
  for (const TrackedObject& o : objects) {
    State s = states_.count(o.id) ? states_.at(o.id) : State{};
    int inside = 0, moving = 0;
    for (const MotionCuePoint& p : points)
      if (p.pixel.x >= o.box.left() && p.pixel.x <= o.box.right() && p.pixel.y >= o.box.top() &&
          p.pixel.y <= o.box.bottom()) {
        ++inside;
        if (p.moving) ++moving;
      }
    if (moving >= 2 && 3 * moving >= inside) {
      s.moved = true;
      s.static_run = 0;
    } else if (!translating) {
      if (inside >= options_.min_points) ++s.static_run;
    } else if (const RangeCheck c = checkRange(o, points); c != RangeCheck::kNothingShown) {
      s.static_run = c == RangeCheck::kAgrees ? s.static_run + 1 : 0;
    }
    next[o.id] = s;
    if (stateOf(s) == ObjectMotion::kStatic) ever_static_.insert(o.id);
  }
  states_ = std::move(next);
}

ObjectMotionClassifier::RangeCheck ObjectMotionClassifier::checkRange(const TrackedObject& o,
                                                                     const std::vector<MotionCuePoint>& points) const {
  const auto height = options_.class_height_m.find(o.class_id);
  if (!camera_ || height == options_.class_height_m.end()) return RangeCheck::kNothingShown;
  // A box the border cuts is shorter than its object.
  if (!camera_->inImage(o.box.left(), o.box.top(), 2.0) || !camera_->inImage(o.box.right(), o.box.bottom(), 2.0))
    return RangeCheck::kNothingShown;
  Eigen::Vector3d top, bottom;
  if (!camera_->unproject(Eigen::Vector2d(o.box.cx, o.box.top()), &top) ||
      !camera_->unproject(Eigen::Vector2d(o.box.cx, o.box.bottom()), &bottom))
    return RangeCheck::kNothingShown;
  const double angle = std::atan2(top.cross(bottom).norm(), top.dot(bottom));
  if (angle <= 0) return RangeCheck::kNothingShown;
  const double range = height->second / (2 * std::tan(angle / 2));
  // The middle half of the box's width, its top and bottom 15 % left out: the object, not what is
  // behind it.
  std::vector<double> expected, ratio;
  for (const MotionCuePoint& p : points) {
    if (p.moving || p.slide_at_1m_px <= 0 || std::abs(p.pixel.x - o.box.cx) > o.box.w / 4 ||
        std::abs(p.pixel.y - o.box.cy) > 0.35 * o.box.h)
      continue;
    expected.push_back(p.slide_at_1m_px / range);
    ratio.push_back(p.slide_px / expected.back());
  }
  if (static_cast<int>(expected.size()) < options_.min_points) return RangeCheck::kNothingShown;
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  if (median(expected) < options_.min_slide_px) return RangeCheck::kNothingShown;
  const double r = median(ratio);  // 1 for static points at the range the object's size says
  return r >= 1 / options_.range_tolerance && r <= options_.range_tolerance ? RangeCheck::kAgrees
                                                                            : RangeCheck::kDisagrees;
}

ObjectMotion ObjectMotionClassifier::stateOf(const State& s) const {
  if (s.moved) return ObjectMotion::kMoving;
  if (options_.static_frames > 0 && s.static_run >= options_.static_frames) return ObjectMotion::kStatic;
  return ObjectMotion::kUnknown;
}

ObjectMotion ObjectMotionClassifier::state(int64_t id) const {
  const auto it = states_.find(id);
  return it == states_.end() ? ObjectMotion::kUnknown : stateOf(it->second);
}

std::set<int64_t> ObjectMotionClassifier::staticIds() const {
  std::set<int64_t> ids;
  for (const auto& [id, s] : states_)
    if (stateOf(s) == ObjectMotion::kStatic) ids.insert(id);
  return ids;
}

}  // namespace adugs::tracking

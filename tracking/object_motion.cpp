#include "tracking/object_motion.h"

namespace adugs::tracking {

void ObjectMotionClassifier::update(const std::vector<TrackedObject>& objects, const std::vector<MotionCuePoint>& points,
                                    bool can_confirm_static) {
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
    } else if (can_confirm_static && inside >= options_.min_points) {
      ++s.static_run;
    }
    next[o.id] = s;
    if (stateOf(s) == ObjectMotion::kStatic) ever_static_.insert(o.id);
  }
  states_ = std::move(next);
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

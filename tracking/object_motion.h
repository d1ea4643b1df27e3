#pragma once
// Whether each tracked object moves, judged by the class-free motion cue's points inside its box
// (tracking/detect/motion_cue.h): a detector's box of a car parked for the whole sequence is the
// most useful static structure of a street, and masking it only loses features. Per object (SORT
// track id), per frame: the cue's points inside its box are counted; moving evidence (at least 2
// moving points, and at least a third of those inside) marks it as having moved, for good (a
// person who stops will walk on); a frame with enough points (min_points) and no such evidence
// extends its static run, but only in frames the cue judged with its rotation-only model (the
// camera did not translate): while the camera translates, an object moving along its epipolar
// lines (coming towards the camera, or going its way more slowly) looks like static structure at
// another depth, so no frame of a translating camera can confirm that an object stands still. A
// parked car is confirmed while the platform stands or turns, and keeps its features after. States:
//   moving   it moved at some frame: masked;
//   static   never moved and static for static_frames frames in a row: not masked, features kept;
//   unknown  neither yet (too young, or too few points on it to judge): masked, as without the cue.
// Objects no longer tracked are forgotten.
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "tracking/detect/motion_cue.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {

enum class ObjectMotion { kUnknown, kMoving, kStatic };

struct ObjectMotionOptions {
  int static_frames = 10;  // judged static this many frames in a row: static (0: never)
  int min_points = 4;      // the cue's points inside the box needed to judge a frame
};

class ObjectMotionClassifier {
 public:
  explicit ObjectMotionClassifier(const ObjectMotionOptions& options = {}) : options_(options) {}

  // This frame's tracked objects and the motion cue's points of the same frame; can_confirm_static:
  // the cue judged this frame without camera translation (!MotionCue::translating()).
  void update(const std::vector<TrackedObject>& objects, const std::vector<MotionCuePoint>& points,
              bool can_confirm_static);
  ObjectMotion state(int64_t id) const;
  // Ids of the tracked objects now static: not to be masked.
  std::set<int64_t> staticIds() const;
  // Distinct objects seen static at some frame so far (for the run's summary).
  size_t everStatic() const { return ever_static_.size(); }

 private:
  struct State {
    bool moved = false;
    int static_run = 0;
  };
  ObjectMotion stateOf(const State& s) const;

  ObjectMotionOptions options_;
  std::map<int64_t, State> states_;
  std::set<int64_t> ever_static_;
};

}  // namespace adugs::tracking

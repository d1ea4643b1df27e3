#pragma once
// Whether each tracked object moves, judged by the class-free motion cue's points inside its box
// (tracking/detect/motion_cue.h): a detector's box of a car parked for the whole sequence is the
// most useful static structure of a street, and masking it only loses features. Per object (SORT
// track id), per frame: the cue's points inside its box are counted; moving evidence (at least 2
// moving points, and at least a third of those inside) marks it as having moved, for good (a
// person who stops will walk on). A frame without such evidence can confirm that it stands still:
//   - camera not translating (the cue's rotation-only model): min_points points inside are enough;
//   - camera translating: an object moving along its epipolar lines (coming towards the camera, or
//     going its way more slowly) looks like static structure at another range, so the points'
//     ranges must agree with the object's size: its class's typical height (class_height_m) over
//     the box's angular height gives its range; the points in the middle of the box (its body,
//     not the background at its sides) slide along their epipolar lines as static points at a
//     range r do (MotionCuePoint::slide_at_1m_px / r); their median slide within range_tolerance
//     of that extends the static run, outside it ends the run. Objects of other classes (or the
//     cue's own boxes), boxes cut by the image border, and frames where a static object would
//     slide less than min_slide_px show nothing.
// States:
//   moving   it moved at some frame: masked;
//   static   never moved and static for static_frames frames in a row: not masked, features kept;
//   unknown  neither yet (too young, or too few points on it to judge): masked, as without the cue.
// Objects no longer tracked are forgotten.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "data/camera_model.h"

#include "tracking/detect/motion_cue.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {

enum class ObjectMotion { kUnknown, kMoving, kStatic };

struct ObjectMotionOptions {
  int static_frames = 10;  // judged static this many frames in a row: static (0: never)
  int min_points = 4;      // the cue's points inside the box needed to judge a frame
  // Typical heights of the detector's classes (COCO ids: person, car, bus), m; a person's
  // 1.6-1.9 m and a car's 1.4-1.7 m are within range_tolerance of these.
  std::map<int, double> class_height_m = {{0, 1.7}, {2, 1.5}, {5, 3.2}};
  double range_tolerance = 1.3;  // the points' median slide within this factor of a static object's
  double min_slide_px = 1.0;     // a static object's expected median slide below this: nothing shown
};

class ObjectMotionClassifier {
 public:
  // camera: the boxes' angular heights for the translating case (without it, only frames without
  // translation can confirm static).
  explicit ObjectMotionClassifier(const ObjectMotionOptions& options = {},
                                  std::optional<data::CameraModel> camera = std::nullopt)
      : options_(options), camera_(std::move(camera)) {}

  // This frame's tracked objects and the motion cue's points of the same frame; translating: the
  // cue judged this frame with camera translation (MotionCue::translating()).
  void update(const std::vector<TrackedObject>& objects, const std::vector<MotionCuePoint>& points,
              bool translating);
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
  enum class RangeCheck { kNothingShown, kAgrees, kDisagrees };
  // The translating camera's check of a still-looking object (see the top of this file).
  RangeCheck checkRange(const TrackedObject& object, const std::vector<MotionCuePoint>& points) const;

  ObjectMotionOptions options_;
  std::optional<data::CameraModel> camera_;
  std::map<int64_t, State> states_;
  std::set<int64_t> ever_static_;
};

}  // namespace adugs::tracking

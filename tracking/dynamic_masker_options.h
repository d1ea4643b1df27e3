#pragma once
// The options of the dynamic-object stage (DynamicMasker), defaults in code, and their one reader:
// the `dynamic:` map of a run config (data/config/*.yaml). `adugs run`/`live` read it from the run
// config, `adugs track --config` from the same file; command-line flags only override fields.
//   detect_every, tracker: sort | none, noise: adaptive | fixed, SORT's max_age / min_hits /
//   iou_min, the adaptive noise's lambda / beta_pos / beta_size / window, erode_radius_px /
//   dilate_radius_px, min_box_side_px, segment_every (0 = auto: 2 for GrabCut, 10 for MobileSAM),
//   segment_async, camera_motion_compensation, appearance_weight, and the association stages
//   high_score / low_iou_min / drop_unconfirmed / last_box_association / direction_weight /
//   direction_frames / recovery; and the map motion_cue: of the class-free motion cue's options
//   (tracking/detect/motion_cue.h: cell_px, corner_quality, threshold_px, translation_min_gain,
//   min_speed, ransac_iterations, group_radius_px, min_points, min_corner_points, corner_ratio,
//   box_margin), used with --mask
//   motion or --motion-cue; static_after_frames / static_min_points (tracking/object_motion.h:
//   with the motion cue, a tracked object judged static this many frames is not masked; 0: never);
//   and the map grabcut: of the GrabCut segmenter's options (tracking/segment/grabcut_segmenter.h:
//   iterations, max_side, prompted_iterations, prompted_max_side, margin, min_box_side, min_foreground_fraction, point_radius_px)
#include <cstdint>

#include "data/formats/yaml_options.h"
#include "tracking/detect/motion_cue.h"
#include "tracking/object_motion.h"
#include "tracking/segment/grabcut_segmenter.h"
#include "tracking/segment/mask_refinement.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {

struct DynamicMaskerOptions {
  SortOptions sort;
  MaskRefinementOptions refinement;
  double min_box_side_px = 4;  // smaller tracked boxes are ignored
  // The detector runs on every detect_every-th frame (1 = all); in between, SORT's predictions
  // carry the boxes (SortTracker::predict), which saves the detector's time at a cost in
  // accuracy measured in doc/results.md.
  int detect_every = 1;
  // false: each frame's detections are segmented as they are, without SORT (the paper's "no
  // SORT" ablation); needs detect_every = 1.
  bool track = true;
  // Frames between a track's box-segmenter runs, its mask carried by its tracked box in between
  // (tracking/segment/sparse_segmenter.h); 0 = automatic (BoxSegmenter::refreshEvery: every 2nd
  // frame for GrabCut, every 10th for MobileSAM, every frame for filled boxes). 1 = every frame.
  int segment_every = 0;
  bool segment_async = true;  // a slow segmenter's sparse runs on a worker thread (false: inline, reproducible)
  // The caller feeds the gyro's image motion to SORT (compensateCameraMotion) when true.
  bool camera_motion_compensation = false;
  MotionCueOptions motion_cue;  // the class-free cue's, when it runs (--mask motion, --motion-cue)
  ObjectMotionOptions object_motion;  // with the cue: objects seen static keep their features
  GrabCutOptions grabcut;             // of the default box segmenter
};

// Reads the keys above from `dynamic:` (unknown keys are left for the caller's finish()); errors
// name file, line and key.
void readDynamicMaskerOptions(data::YamlOptionsReader& r, DynamicMaskerOptions* options);

// The one rule for which frames the detector runs on: every detect_every-th frame from the first
// (frame_index counts from 0). The frames between get SORT's predictions.
inline bool isDetectionFrame(int64_t frame_index, int detect_every) { return frame_index % detect_every == 0; }

}  // namespace adugs::tracking

#pragma once
// The dynamic-object stage after detection (doc/architecture.md "The method"), per frame:
//   detections -> enhanced SORT (tracked + coasting boxes) -> box-prompted segmentation (union)
//   -> refinement (erode S_erode, dilate S_dilate) -> dynamic mask (255 = do not use for VIO).
// Detection is run by the caller (a tracking/detect/detector.h backend, on the frames
// isDetectionFrame() names) so that ground-truth or recorded detections can be fed the same way.
#include <map>
#include <memory>
#include <set>
#include <opencv2/core.hpp>
#include <vector>

#include "tracking/detect/motion_cue.h"
#include "tracking/dynamic_masker_options.h"
#include "tracking/segment/box_segmenter.h"
#include "tracking/segment/mask_refinement.h"
#include "tracking/segment/sparse_segmenter.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {

struct DynamicMaskResult {
  cv::Mat mask;                        // CV_8UC1, image size, 0/255
  std::vector<TrackedObject> objects;  // what SORT reported (detected and coasting)
  double masked_fraction = 0;          // of the image
  double sort_ms = 0, segment_ms = 0, refine_ms = 0;
};

// The motion cue's points as prompts for the box segmenter: its moving points are object, its
// still ones background (points of neither kind are left out).
std::vector<PointPrompt> cuePointPrompts(const std::vector<MotionCuePoint>& points);

class DynamicMasker {
 public:
  DynamicMasker(const DynamicMaskerOptions& options, std::unique_ptr<BoxSegmenter> segmenter);
  // The camera's image motion since the previous frame (previous pixel -> current pixel), applied
  // to the tracks before this frame's process()/carry() (SortTracker::compensateCameraMotion).
  void compensateCameraMotion(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map) {
    sort_.compensateCameraMotion(map);
  }
  // Tracked objects (SORT ids) seen static (tracking/object_motion.h): from the next frame on
  // they are not segmented, so their features are kept. Replaces the previous set.
  void setStaticObjects(std::set<int64_t> ids) { static_ids_ = std::move(ids); }
  // image: CV_8UC1 or CV_8UC3; detections of this frame in its pixels; points: the motion cue's
  // point prompts of this frame, for the segmentation of its own boxes (class kMovingClass; used
  // by GrabCut, ignored by a sparse segmenter).
  DynamicMaskResult process(const cv::Mat& image, const std::vector<Detection>& detections,
                            const std::vector<PointPrompt>& points = {});
  // A frame without detections (not a detection frame): the tracked boxes predicted to it.
  DynamicMaskResult carry(const cv::Mat& image);
  const BoxSegmenter& segmenter() const { return sparse_ ? sparse_->inner() : *segmenter_; }
  // Runs of the box segmenter so far when it runs sparsely (-1 when it runs on every frame).
  int segmenterRuns() const { return sparse_ ? sparse_->innerRuns() : -1; }
  int64_t boxesSegmented() const { return sparse_ ? sparse_->boxesSegmented() : -1; }

 private:
  DynamicMaskResult maskBoxes(const cv::Mat& image, DynamicMaskResult r, const std::vector<PointPrompt>& points = {});

  DynamicMaskerOptions options_;
  std::unique_ptr<BoxSegmenter> segmenter_;      // every frame, or
  std::unique_ptr<SparseSegmenter> sparse_;      // sparsely
  SortTracker sort_;
  int frames_since_detection_;  // starts at detect_every: the first frame is detected
  std::set<int64_t> static_ids_;
};

}  // namespace adugs::tracking

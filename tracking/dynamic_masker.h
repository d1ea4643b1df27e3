#pragma once
// The dynamic-object stage of DESIGN.md after detection, per frame:
//   detections -> enhanced SORT (tracked + coasting boxes) -> box-prompted segmentation (union)
//   -> refinement (erode S_erode, dilate S_dilate) -> dynamic mask (255 = do not use for VIO).
// Detection is run by the caller (tracking/object_detector.h) so that ground-truth or recorded
// detections can be fed the same way.
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "tracking/box_segmenter.h"
#include "tracking/mask_refinement.h"
#include "tracking/sort_tracker.h"
#include "tracking/sparse_segmenter.h"

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
  // Frames between box-segmenter runs, the masks carried by the tracked boxes in between
  // (tracking/sparse_segmenter.h); 0 = automatic: every frame, every 10th for a slow segmenter
  // (MobileSAM). 1 = every frame.
  int segment_every = 0;
  bool segment_async = true;  // sparse runs on a worker thread (false: inline, reproducible)
  // The caller feeds the gyro's image motion to SORT (compensateCameraMotion) when true.
  bool camera_motion_compensation = false;
};

struct DynamicMaskResult {
  cv::Mat mask;                        // CV_8UC1, image size, 0/255
  std::vector<TrackedObject> objects;  // what SORT reported (detected and coasting)
  double masked_fraction = 0;          // of the image
  double sort_ms = 0, segment_ms = 0, refine_ms = 0;
};

class DynamicMasker {
 public:
  DynamicMasker(const DynamicMaskerOptions& options, std::unique_ptr<BoxSegmenter> segmenter);
  // The camera's image motion since the previous frame (previous pixel -> current pixel), applied
  // to the tracks before this frame's process()/carry() (SortTracker::compensateCameraMotion).
  void compensateCameraMotion(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map) {
    sort_.compensateCameraMotion(map);
  }
  // Whether the next frame is one the detector should run on.
  bool detectionDue() const { return frames_since_detection_ >= options_.detect_every; }
  // image: CV_8UC1 or CV_8UC3; detections of this frame in its pixels.
  DynamicMaskResult process(const cv::Mat& image, const std::vector<Detection>& detections);
  // A frame without detections (not detectionDue()): the tracked boxes predicted to it.
  DynamicMaskResult carry(const cv::Mat& image);
  const BoxSegmenter& segmenter() const { return sparse_ ? sparse_->inner() : *segmenter_; }
  // Runs of the box segmenter so far when it runs sparsely (-1 when it runs on every frame).
  int segmenterRuns() const { return sparse_ ? sparse_->innerRuns() : -1; }

 private:
  DynamicMaskResult maskBoxes(const cv::Mat& image, DynamicMaskResult r);

  DynamicMaskerOptions options_;
  std::unique_ptr<BoxSegmenter> segmenter_;      // every frame, or
  std::unique_ptr<SparseSegmenter> sparse_;      // sparsely
  SortTracker sort_;
  int frames_since_detection_;  // starts at detect_every: the first frame is detected
};

}  // namespace adugs::tracking

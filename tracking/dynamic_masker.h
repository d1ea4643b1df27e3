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

namespace adugs::tracking {

struct DynamicMaskerOptions {
  SortOptions sort;
  MaskRefinementOptions refinement;
  double min_box_side_px = 4;  // smaller tracked boxes are ignored
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
  // image: CV_8UC1 or CV_8UC3; detections of this frame in its pixels.
  DynamicMaskResult process(const cv::Mat& image, const std::vector<Detection>& detections);
  const BoxSegmenter& segmenter() const { return *segmenter_; }

 private:
  DynamicMaskerOptions options_;
  std::unique_ptr<BoxSegmenter> segmenter_;
  SortTracker sort_;
};

}  // namespace adugs::tracking

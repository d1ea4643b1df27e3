#pragma once
// Weight-free box-prompted segmentation with OpenCV's GrabCut (colour/grey-level GMMs + graph
// cut), initialised with the box as "probably foreground" inside and certain background in a
// margin around it. For speed the region is processed at most max_side px wide/high.
// Safety first for the VIO: when GrabCut returns (almost) nothing for a box - a textureless
// object, a box too small to model - the whole box is masked instead.
#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {

struct GrabCutOptions {
  int iterations = 2;
  int max_side = 96;                      // px of the (box + margin) region after downscaling
  double margin = 0.15;                   // background ring around the box, fraction of its size
  int min_box_side = 12;                  // px; smaller boxes are filled directly
  double min_foreground_fraction = 0.15;  // of the box area; less -> fill the box
};

class GrabCutSegmenter : public BoxSegmenter {
 public:
  explicit GrabCutSegmenter(const GrabCutOptions& options = {});
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override;
  const char* name() const override { return "grabcut"; }
  // How many boxes fell back to the filled box in the last call.
  int lastFallbacks() const { return fallbacks_; }

 private:
  // Object pixels of one box, CV_8UC1 of the clipped box size.
  cv::Mat segmentOne(const cv::Mat& bgr, const Box& box, const cv::Rect& box_rect);
  GrabCutOptions options_;
  int fallbacks_ = 0;
};

}  // namespace adugs::tracking

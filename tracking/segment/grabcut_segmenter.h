#pragma once
// Weight-free box-prompted segmentation with OpenCV's GrabCut (colour/grey-level GMMs + graph
// cut), initialised with the box as "probably foreground" inside and certain background in a
// margin around it. For speed the region is processed at most max_side px wide/high.
// Point prompts inside a box are hard labels for the graph cut (a disc of point_radius_px each):
// object points foreground, background points background, so that a loose box (the motion cue's
// boxes are the bounding boxes of moving points) is cut down to the object.
// Safety first for the VIO: when GrabCut returns (almost) nothing for a box - a textureless
// object, a box too small to model - the whole box is masked instead.
#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {

struct GrabCutOptions {
  int iterations = 2;
  int max_side = 96;                      // px of the (box + margin) region after downscaling
  // A box with point prompts inside: the hard labels carry the cut, and 1 iteration at 48 px gives
  // the motion cue's masks the recall and precision of 2 at 96 px at a quarter of the cost
  // (GrabCut's first iteration, its graph cut above all, is most of its time and grows faster
  // than the pixels; doc/results.md, "GrabCut's cost"). Without prompts, fewer pixels or
  // iterations fall back to the filled box more often.
  int prompted_iterations = 1;
  int prompted_max_side = 48;
  double margin = 0.15;                   // background ring around the box, fraction of its size
  int min_box_side = 12;                  // px; smaller boxes are filled directly
  double min_foreground_fraction = 0.15;  // of the box area; less -> fill the box
  double point_radius_px = 3;             // of a point prompt's hard label, in image pixels
};

class GrabCutSegmenter : public BoxSegmenter {
 public:
  explicit GrabCutSegmenter(const GrabCutOptions& options = {});
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override;
  cv::Mat segmentWithPoints(const cv::Mat& image, const std::vector<Box>& boxes,
                            const std::vector<PointPrompt>& points) override;
  const char* name() const override { return "grabcut"; }
  // Each box's mask every 2nd frame, carried by its box in between. Every 3rd frame (half the
  // cost again) kept the masks' recall and precision, but on Table I's street the carried masks
  // cost the motion cue 1.45x its ATE (median 0.070 -> 0.102 m over 8 seeds); every 2nd frame
  // gives 0.69x every 3rd's there (0.98x in the room, 1.01x on the moving-box flights) for 1.03x
  // the wall (doc/results.md, "Masks carried between GrabCut runs").
  int refreshEvery() const override { return 2; }
  // How many boxes fell back to the filled box in the last call.
  int lastFallbacks() const { return fallbacks_; }

 private:
  // Object pixels of one box, CV_8UC1 of the clipped box size; image grey or BGR.
  cv::Mat segmentOne(const cv::Mat& image, const Box& box, const cv::Rect& box_rect,
                     const std::vector<PointPrompt>& points);
  GrabCutOptions options_;
  int fallbacks_ = 0;
};

}  // namespace adugs::tracking

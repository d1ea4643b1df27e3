#pragma once
// Box-prompted segmentation (doc/architecture.md, "The method"): each tracked object box prompts a
// segmenter for the object's pixels; the union over the boxes is the raw dynamic mask (refined
// afterwards by tracking/segment/mask_refinement). Backends: the weight-free GrabCut segmenter
// (default) and MobileSAM when the user supplies its TorchScript files.
#include <opencv2/core.hpp>
#include <vector>

#include "tracking/box.h"

namespace adugs::tracking {

// A point prompt: a pixel known to be on a moving object or on the static background (the
// motion cue's moving and still points), used inside the boxes it falls in.
struct PointPrompt {
  cv::Point2f pixel;
  bool object = false;
};

class BoxSegmenter {
 public:
  virtual ~BoxSegmenter() = default;
  // image: CV_8UC1 or CV_8UC3. Returns CV_8UC1 of the image size, 255 on object pixels of any
  // box, 0 elsewhere. Boxes may extend past the image; they are clipped.
  virtual cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) = 0;
  // The same with point prompts; a segmenter that cannot use them ignores them.
  virtual cv::Mat segmentWithPoints(const cv::Mat& image, const std::vector<Box>& boxes,
                                    const std::vector<PointPrompt>& /*points*/) {
    return segment(image, boxes);
  }
  virtual const char* name() const = 0;
  // Too slow to run on every frame on a CPU, and one costly run serves every box (an image
  // encoder): the dynamic masker then runs it sparsely on a worker thread, all boxes at once.
  virtual bool slow() const { return false; }
  // Frames between a track's fresh masks (carried by its box in between) when the run config
  // leaves `dynamic: segment_every` automatic (tracking/segment/sparse_segmenter.h).
  virtual int refreshEvery() const { return 1; }
};

// The integer pixel rectangle of a box clipped to a width x height image (may be empty).
cv::Rect clippedRect(const Box& box, int width, int height);

// The filled boxes themselves: the most conservative mask (and what the others fall back to).
class FilledBoxSegmenter : public BoxSegmenter {
 public:
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override;
  const char* name() const override { return "box"; }
};

}  // namespace adugs::tracking

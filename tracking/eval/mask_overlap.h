#pragma once
// How a frame's dynamic mask covers the exact mask of the movers (the simulator's mav0/mask0):
// the pixel counts behind summary.yaml's recall (covered / exact) and precision (covered / masked),
// over the whole image, inside one class's boxes, or inside one cue's boxes. Both masks are
// CV_8UC1 of the same size, nonzero = in. One pass over the pixels, no image allocated; the counts
// inside boxes look only at the boxes' pixels (a pixel in several boxes counts once).
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace adugs::tracking {

struct MaskOverlap {
  int64_t exact = 0;    // pixels of the exact mask
  int64_t masked = 0;   // pixels of the dynamic mask
  int64_t covered = 0;  // pixels of both
};

// Over the whole image. Masks of different sizes or types: std::invalid_argument.
MaskOverlap maskOverlap(const cv::Mat& exact, const cv::Mat& mask);

// Over the union of the boxes (clipped to the image; empty boxes ignored).
MaskOverlap maskOverlapInBoxes(const cv::Mat& exact, const cv::Mat& mask, const std::vector<cv::Rect>& boxes);

}  // namespace adugs::tracking

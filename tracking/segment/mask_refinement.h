#pragma once
// Refines the union of segmented object masks so it covers object edges (doc/architecture.md, "The
// method"):
// erosion with a circular element S_erode removes speckles and thin false positives, then
// dilation with a larger circular element S_dilate grows the mask over the blurred object border.
#include <opencv2/core.hpp>

namespace adugs::tracking {

struct MaskRefinementOptions {
  int erode_radius_px = 2;   // S_erode: disk of this radius (0 = no erosion)
  int dilate_radius_px = 6;  // S_dilate: disk of this radius, must exceed erode_radius_px
};

// mask: CV_8UC1, 255 = dynamic. Returns a new binary mask (0/255) of the same size.
// Throws std::invalid_argument on an empty or non-8-bit mask or inconsistent radii.
cv::Mat refineDynamicMask(const cv::Mat& mask, const MaskRefinementOptions& options);

// The circular structuring element of the given radius: (2r+1)x(2r+1), 1 inside the disk.
cv::Mat diskElement(int radius_px);

}  // namespace adugs::tracking

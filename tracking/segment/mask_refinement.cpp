#include "tracking/segment/mask_refinement.h"

#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace adugs::tracking {

cv::Mat diskElement(int radius_px) {
  if (radius_px < 0) throw std::invalid_argument("disk radius must be >= 0");
  const int size = 2 * radius_px + 1;
  cv::Mat disk(size, size, CV_8UC1, cv::Scalar(0));
  // Pixel (x, y) is in the disk when its centre is within radius_px of the centre pixel
  // (radius 1 gives the 3x3 cross).
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const int dx = x - radius_px, dy = y - radius_px;
      if (dx * dx + dy * dy <= radius_px * radius_px) disk.at<uint8_t>(y, x) = 1;
    }
  return disk;
}

cv::Mat refineDynamicMask(const cv::Mat& mask, const MaskRefinementOptions& options) {
  if (mask.empty() || mask.type() != CV_8UC1)
    throw std::invalid_argument("dynamic mask must be a non-empty CV_8UC1 image");
  if (options.erode_radius_px < 0 || options.dilate_radius_px <= options.erode_radius_px)
    throw std::invalid_argument("mask refinement needs 0 <= erode radius (" +
                                std::to_string(options.erode_radius_px) + ") < dilate radius (" +
                                std::to_string(options.dilate_radius_px) + ")");
  const cv::Mat binary = mask > 0;  // 0/255
  cv::Mat refined(binary.size(), CV_8UC1, cv::Scalar(0));
  // Only around the masked pixels: their bounding box grown by both radii, within which every
  // pixel the two operations can set lies and every masked pixel sees its whole disk, so the
  // result is the whole image's (tested). The masks cover a few % of the image, and the
  // morphology over all of it was a share of the masking stage.
  const cv::Rect masked = cv::boundingRect(binary);
  if (masked.empty()) return refined;
  const int pad = options.erode_radius_px + options.dilate_radius_px;
  const cv::Rect roi = (masked + cv::Point(-pad, -pad) + cv::Size(2 * pad, 2 * pad)) &
                       cv::Rect(0, 0, binary.cols, binary.rows);
  cv::Mat eroded;
  if (options.erode_radius_px > 0)
    // Default border: an object cut by the image edge is not eroded from that edge (the region's
    // edges inside the image have only unmasked pixels within the erosion radius).
    cv::erode(binary(roi), eroded, diskElement(options.erode_radius_px));
  else
    eroded = binary(roi);
  cv::dilate(eroded, refined(roi), diskElement(options.dilate_radius_px));
  return refined;
}

}  // namespace adugs::tracking

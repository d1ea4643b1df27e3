#include "tracking/segment/box_segmenter.h"

#include <algorithm>
#include <cmath>

namespace adugs::tracking {

cv::Rect clippedRect(const Box& box, int width, int height) {
  const int x0 = std::max(0, static_cast<int>(std::floor(box.left())));
  const int y0 = std::max(0, static_cast<int>(std::floor(box.top())));
  const int x1 = std::min(width, static_cast<int>(std::ceil(box.right())));
  const int y1 = std::min(height, static_cast<int>(std::ceil(box.bottom())));
  if (x1 <= x0 || y1 <= y0) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

cv::Mat FilledBoxSegmenter::segment(const cv::Mat& image, const std::vector<Box>& boxes) {
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  for (const Box& b : boxes) {
    const cv::Rect r = clippedRect(b, image.cols, image.rows);
    if (!r.empty()) mask(r).setTo(255);
  }
  return mask;
}

}  // namespace adugs::tracking

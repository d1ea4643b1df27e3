#include "vio/frontend/feature_overlay.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace adugs::vio {

cv::Scalar lifetimeColor(int track_count, int saturate_lifetime) {
  // 0 -> blue, 0.5 -> green, 1 -> red, by linear blends.
  const double t = std::clamp((track_count - 1.0) / std::max(1, saturate_lifetime - 1), 0.0, 1.0);
  if (t < 0.5) return {255 * (1 - 2 * t), 255 * 2 * t, 0};
  return {0, 255 * (2 - 2 * t), 255 * (2 * t - 1)};
}

cv::Mat drawFeatureOverlay(const cv::Mat& image, const FrameFeatures& f, const cv::Mat& mask,
                           const std::vector<cv::Point2f>& dropped_dynamic,
                           const std::vector<cv::Point2f>& rejected,
                           const FeatureOverlayStyle& style) {
  cv::Mat out;
  if (image.type() == CV_8UC1) {
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  } else if (image.type() == CV_8UC3) {
    out = image.clone();
  } else {
    throw std::invalid_argument("drawFeatureOverlay: image must be CV_8UC1 or CV_8UC3");
  }
  if (!mask.empty()) {
    if (mask.type() != CV_8UC1 || mask.size() != image.size())
      throw std::invalid_argument("drawFeatureOverlay: mask must be CV_8UC1 of the image's size");
    cv::Mat tinted;
    cv::addWeighted(out, 1.0 - style.mask_alpha,
                    cv::Mat(out.size(), CV_8UC3, cv::Scalar(0, 0, 255)), style.mask_alpha, 0.0,
                    tinted);
    tinted.copyTo(out, mask);
  }
  auto cross = [&](const cv::Point2f& p, const cv::Scalar& c) {
    cv::drawMarker(out, p, c, cv::MARKER_TILTED_CROSS, 2 * style.radius + 3, 1, cv::LINE_AA);
  };
  for (const auto& p : dropped_dynamic) cross(p, {255, 0, 255});
  for (const auto& p : rejected) cross(p, {0, 255, 255});
  for (size_t i = 0; i < f.size(); ++i) {
    const cv::Scalar c = lifetimeColor(f.track_counts[i], style.saturate_lifetime);
    if (i < f.prev_pixels.size()) cv::line(out, f.prev_pixels[i], f.pixels[i], c, 1, cv::LINE_AA);
    cv::circle(out, f.pixels[i], style.radius, c, cv::FILLED, cv::LINE_AA);
  }
  return out;
}

}  // namespace adugs::vio

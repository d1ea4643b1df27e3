#include "tracking/detect/letterbox.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace adugs::tracking {

Box Letterbox::toImage(const Box& b) const {
  return {(b.cx - offset.x) / scale, (b.cy - offset.y) / scale, b.w / scale, b.h / scale};
}

Letterbox letterbox(const cv::Mat& image, cv::Size input_size, LetterboxPlacement placement) {
  cv::Mat bgr = image;
  if (image.channels() == 1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  Letterbox out;
  out.scale = std::min(static_cast<double>(input_size.width) / bgr.cols,
                       static_cast<double>(input_size.height) / bgr.rows);
  cv::Size resized_size;
  if (placement == LetterboxPlacement::kTopLeft) {
    resized_size = {static_cast<int>(bgr.cols * out.scale), static_cast<int>(bgr.rows * out.scale)};
  } else {
    resized_size = {static_cast<int>(std::lround(bgr.cols * out.scale)),
                    static_cast<int>(std::lround(bgr.rows * out.scale))};
    // dw - 0.1 is never a tie (dw is a multiple of 0.5), so lround equals Python's round here.
    const double dw = (input_size.width - resized_size.width) / 2.0;
    const double dh = (input_size.height - resized_size.height) / 2.0;
    out.offset = {static_cast<double>(std::lround(dw - 0.1)), static_cast<double>(std::lround(dh - 0.1))};
  }
  cv::Mat resized = bgr;
  if (resized_size != bgr.size()) cv::resize(bgr, resized, resized_size, 0, 0, cv::INTER_LINEAR);
  out.image = cv::Mat(input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  resized.copyTo(out.image(cv::Rect(static_cast<int>(out.offset.x), static_cast<int>(out.offset.y),
                                    resized.cols, resized.rows)));
  return out;
}

}  // namespace adugs::tracking

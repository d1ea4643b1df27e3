#include "tracking/segment/sam_transforms.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace adugs::tracking {
namespace {
// SAM's pixel normalisation, RGB order (segment_anything/modeling/sam.py).
const cv::Scalar kPixelMeanRgb(123.675, 116.28, 103.53);
const cv::Scalar kPixelStdRgb(58.395, 57.12, 57.375);
}  // namespace

cv::Size samResizedSize(cv::Size image_size) {
  if (image_size.width <= 0 || image_size.height <= 0)
    throw std::invalid_argument("samResizedSize: empty image");
  const double scale =
      static_cast<double>(kSamImageSize) / std::max(image_size.width, image_size.height);
  return {static_cast<int>(image_size.width * scale + 0.5),
          static_cast<int>(image_size.height * scale + 0.5)};
}

cv::Mat samEncoderInput(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("samEncoderInput: image must be 8-bit grey or BGR");
  cv::Mat rgb;
  cv::cvtColor(image, rgb, image.channels() == 1 ? cv::COLOR_GRAY2RGB : cv::COLOR_BGR2RGB);
  const cv::Size resized_size = samResizedSize(image.size());
  cv::Mat resized;
  const bool shrinking = resized_size.width < image.cols;
  cv::resize(rgb, resized, resized_size, 0, 0, shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat normalised;
  resized.convertTo(normalised, CV_32FC3);
  cv::subtract(normalised, kPixelMeanRgb, normalised);
  cv::divide(normalised, kPixelStdRgb, normalised);

  // NCHW blob; the padding (bottom/right) is 0 after normalisation, as in Sam.preprocess.
  const int dims[] = {1, 3, kSamImageSize, kSamImageSize};
  cv::Mat blob(4, dims, CV_32F, cv::Scalar(0));
  std::vector<cv::Mat> planes;
  cv::split(normalised, planes);
  for (int c = 0; c < 3; ++c) {
    cv::Mat channel(kSamImageSize, kSamImageSize, CV_32F, blob.ptr<float>(0, c));
    planes[c].copyTo(channel(cv::Rect(cv::Point(0, 0), resized_size)));
  }
  return blob;
}

cv::Vec4f samBoxPrompt(const Box& box, cv::Size image_size) {
  const cv::Size resized = samResizedSize(image_size);
  const double sx = static_cast<double>(resized.width) / image_size.width;
  const double sy = static_cast<double>(resized.height) / image_size.height;
  return {static_cast<float>(box.left() * sx), static_cast<float>(box.top() * sy),
          static_cast<float>(box.right() * sx), static_cast<float>(box.bottom() * sy)};
}

cv::Mat samUpscaleLowResMask(const cv::Mat& low_res_logits, cv::Size image_size) {
  if (low_res_logits.type() != CV_32FC1 || low_res_logits.rows != kSamLowResMaskSize ||
      low_res_logits.cols != kSamLowResMaskSize)
    throw std::invalid_argument("samUpscaleLowResMask: expected 256 x 256 CV_32F logits");
  // Bilinear with half-pixel centres, as F.interpolate(..., align_corners=False).
  cv::Mat padded_frame;
  cv::resize(low_res_logits, padded_frame, cv::Size(kSamImageSize, kSamImageSize), 0, 0,
             cv::INTER_LINEAR);
  const cv::Mat cropped = padded_frame(cv::Rect(cv::Point(0, 0), samResizedSize(image_size)));
  cv::Mat logits;
  cv::resize(cropped, logits, image_size, 0, 0, cv::INTER_LINEAR);
  return logits;
}

}  // namespace adugs::tracking

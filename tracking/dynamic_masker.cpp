#include "tracking/dynamic_masker.h"

#include <chrono>
#include <stdexcept>

namespace adugs::tracking {
namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

DynamicMasker::DynamicMasker(const DynamicMaskerOptions& options,
                             std::unique_ptr<BoxSegmenter> segmenter)
    : options_(options), segmenter_(std::move(segmenter)), sort_(options.sort) {
  if (!segmenter_) throw std::invalid_argument("DynamicMasker: no segmenter");
}

DynamicMaskResult DynamicMasker::process(const cv::Mat& image,
                                         const std::vector<Detection>& detections) {
  DynamicMaskResult r;
  auto t0 = std::chrono::steady_clock::now();
  r.objects = sort_.update(detections);
  r.sort_ms = msSince(t0);

  std::vector<Box> boxes;
  for (const TrackedObject& o : r.objects)
    if (o.box.w >= options_.min_box_side_px && o.box.h >= options_.min_box_side_px)
      boxes.push_back(o.box);
  t0 = std::chrono::steady_clock::now();
  const cv::Mat raw = segmenter_->segment(image, boxes);
  r.segment_ms = msSince(t0);

  t0 = std::chrono::steady_clock::now();
  r.mask = refineDynamicMask(raw, options_.refinement);
  r.refine_ms = msSince(t0);
  r.masked_fraction = static_cast<double>(cv::countNonZero(r.mask)) / (image.rows * image.cols);
  return r;
}

}  // namespace adugs::tracking

#include "tracking/dynamic_masker.h"

#include "data/elapsed_time.h"
#include "tracking/detect/motion_cue.h"
#include "tracking/sort/appearance.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace adugs::tracking {
DynamicMasker::DynamicMasker(const DynamicMaskerOptions& options,
                             std::unique_ptr<BoxSegmenter> segmenter)
    : options_(options),
      segmenter_(std::move(segmenter)),
      sort_(options.sort),
      frames_since_detection_(options.detect_every) {
  if (!segmenter_) throw std::invalid_argument("DynamicMasker: no segmenter");
  if (options_.detect_every < 1) throw std::invalid_argument("DynamicMasker: detect_every must be >= 1");
  if (!options_.track && options_.detect_every != 1)
    throw std::invalid_argument("DynamicMasker: detecting every n-th frame needs the tracker to carry the boxes");
  if (options_.segment_every < 0) throw std::invalid_argument("DynamicMasker: segment_every must be >= 0");
  const int every = options_.segment_every > 0 ? options_.segment_every : segmenter_->refreshEvery();
  if (every > 1) {
    if (!options_.track) throw std::invalid_argument("DynamicMasker: sparse segmentation needs the tracker's ids");
    // The worker thread is for a segmenter too slow to wait for; a per-box one runs inline.
    const bool asynchronous = options_.segment_async && segmenter_->slow();
    sparse_ = std::make_unique<SparseSegmenter>(std::move(segmenter_), SparseSegmenterOptions{every, 0.25, asynchronous});
  }
}

DynamicMaskResult DynamicMasker::process(const cv::Mat& image, const std::vector<Detection>& detections,
                                         const std::vector<PointPrompt>& points) {
  DynamicMaskResult r;
  auto t0 = std::chrono::steady_clock::now();
  if (options_.track && options_.sort.appearance_weight > 0) {
    std::vector<Detection> described = detections;
    for (Detection& d : described) d.appearance = boxHistogram(image, d.box);
    r.objects = sort_.update(described, frames_since_detection_);
  } else if (options_.track) {
    // dt: the frames since the last detection, so the filter's velocity stays per frame.
    r.objects = sort_.update(detections, frames_since_detection_);
  } else {
    for (const Detection& d : detections) r.objects.push_back({0, d.box, d.class_id, true, 1, 0});
  }
  frames_since_detection_ = 1;
  r.sort_ms = data::msSince(t0);
  return maskBoxes(image, std::move(r), points);
}

DynamicMaskResult DynamicMasker::carry(const cv::Mat& image) {
  DynamicMaskResult r;
  auto t0 = std::chrono::steady_clock::now();
  r.objects = sort_.predict(frames_since_detection_);
  ++frames_since_detection_;
  r.sort_ms = data::msSince(t0);
  return maskBoxes(image, std::move(r));
}

std::vector<PointPrompt> cuePointPrompts(const std::vector<MotionCuePoint>& points) {
  std::vector<PointPrompt> prompts;
  for (const MotionCuePoint& p : points)
    if (p.moving || p.still) prompts.push_back({p.pixel, p.moving});
  return prompts;
}

DynamicMaskResult DynamicMasker::maskBoxes(const cv::Mat& image, DynamicMaskResult r,
                                           const std::vector<PointPrompt>& points) {
  auto t0 = std::chrono::steady_clock::now();
  std::vector<TrackedObject> objects;
  for (const TrackedObject& o : r.objects)
    if (o.box.w >= options_.min_box_side_px && o.box.h >= options_.min_box_side_px && !static_ids_.count(o.id))
      objects.push_back(o);
  const cv::Mat raw = sparse_ ? sparse_->segment(image, objects, points) : segmentObjects(*segmenter_, image, objects, points);
  r.segment_ms = data::msSince(t0);

  t0 = std::chrono::steady_clock::now();
  r.mask = refineDynamicMask(raw, options_.refinement);
  r.refine_ms = data::msSince(t0);
  r.masked_fraction = static_cast<double>(cv::countNonZero(r.mask)) / (image.rows * image.cols);
  return r;
}

}  // namespace adugs::tracking

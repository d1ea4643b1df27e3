#include "tracking/segment/grabcut_segmenter.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace adugs::tracking {
namespace {

// GrabCut starts its colour models with k-means, whose first centres OpenCV draws from the
// thread's generator (cv::theRNG). Started from this state on every call, a box's mask depends
// on the image and the box alone, not on which boxes and frames the thread segmented before; the
// caller's generator is given back as it was.
class FixedOpenCvRng {
 public:
  FixedOpenCvRng() : saved_(cv::theRNG().state) { cv::theRNG().state = 0x9e3779b97f4a7c15ULL; }
  ~FixedOpenCvRng() { cv::theRNG().state = saved_; }
  FixedOpenCvRng(const FixedOpenCvRng&) = delete;
  FixedOpenCvRng& operator=(const FixedOpenCvRng&) = delete;

 private:
  uint64_t saved_;
};

}  // namespace

GrabCutSegmenter::GrabCutSegmenter(const GrabCutOptions& options) : options_(options) {
  if (options_.iterations < 1 || options_.max_side < 16 || options_.prompted_iterations < 1 ||
      options_.prompted_max_side < 16 || options_.margin < 0 ||
      options_.min_foreground_fraction < 0 || options_.min_foreground_fraction >= 1)
    throw std::invalid_argument("GrabCutSegmenter: invalid options");
}

cv::Mat GrabCutSegmenter::segment(const cv::Mat& image, const std::vector<Box>& boxes) {
  return segmentWithPoints(image, boxes, {});
}

cv::Mat GrabCutSegmenter::segmentWithPoints(const cv::Mat& image, const std::vector<Box>& boxes,
                                            const std::vector<PointPrompt>& points) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("GrabCutSegmenter: image must be 8-bit grey or BGR");
  fallbacks_ = 0;
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  for (const Box& b : boxes) {
    const cv::Rect r = clippedRect(b, image.cols, image.rows);
    if (r.empty()) continue;
    cv::Mat object = segmentOne(image, b, r, points);
    cv::Mat target = mask(r);
    cv::bitwise_or(target, object, target);
  }
  return mask;
}

cv::Mat GrabCutSegmenter::segmentOne(const cv::Mat& image, const Box& box, const cv::Rect& box_rect,
                                     const std::vector<PointPrompt>& points) {
  cv::Mat filled(box_rect.size(), CV_8UC1, cv::Scalar(255));
  if (std::min(box_rect.width, box_rect.height) < options_.min_box_side) {
    ++fallbacks_;
    return filled;
  }
  // Region = box + margin ring (clipped); GrabCut needs some certain background around the box.
  Box grown = box;
  grown.w *= 1 + 2 * options_.margin;
  grown.h *= 1 + 2 * options_.margin;
  const cv::Rect region = clippedRect(grown, image.cols, image.rows);
  const auto inBox = [&](const PointPrompt& p) {
    return box_rect.contains(cv::Point(static_cast<int>(p.pixel.x), static_cast<int>(p.pixel.y)));
  };
  const bool prompted = std::any_of(points.begin(), points.end(), inBox);
  const int max_side = prompted ? options_.prompted_max_side : options_.max_side;
  const double scale = std::min(1.0, static_cast<double>(max_side) / std::max(region.width, region.height));
  // A grey image is made colour (GrabCut's models are of colour) after the downscaling: the same
  // pixels as downscaling its colour copy, for a fraction of the work.
  cv::Mat small;
  cv::resize(image(region), small, cv::Size(), scale, scale, cv::INTER_AREA);
  if (small.channels() == 1) cv::cvtColor(small, small, cv::COLOR_GRAY2BGR);
  cv::Rect box_small(cv::Point(static_cast<int>((box_rect.x - region.x) * scale),
                               static_cast<int>((box_rect.y - region.y) * scale)),
                     cv::Size(std::max(1, static_cast<int>(box_rect.width * scale)),
                              std::max(1, static_cast<int>(box_rect.height * scale))));
  box_small &= cv::Rect(0, 0, small.cols, small.rows);
  // Where the box touches the image border there is no background ring; GrabCut's rect mode
  // then sees no background at all on that side, which is fine for its GMM as long as some
  // remains elsewhere. A box covering the whole region cannot be modelled: fill it.
  if (box_small.area() >= small.cols * small.rows) {
    ++fallbacks_;
    return filled;
  }
  // The rectangle's labels (certain background outside the box, probable object inside), with
  // the point prompts inside the box as hard labels.
  cv::Mat labels(small.size(), CV_8UC1, cv::Scalar(cv::GC_BGD));
  labels(box_small).setTo(cv::GC_PR_FGD);
  const int radius = std::max(1, static_cast<int>(std::lround(options_.point_radius_px * scale)));
  for (const PointPrompt& p : points) {
    if (!inBox(p)) continue;
    const cv::Point at(static_cast<int>((p.pixel.x - region.x) * scale), static_cast<int>((p.pixel.y - region.y) * scale));
    cv::circle(labels, at, radius, cv::Scalar(p.object ? cv::GC_FGD : cv::GC_BGD), cv::FILLED);
  }
  cv::Mat bgd_model, fgd_model;
  const FixedOpenCvRng fixed_start;
  cv::grabCut(small, labels, box_small, bgd_model, fgd_model, prompted ? options_.prompted_iterations : options_.iterations,
              prompted ? cv::GC_INIT_WITH_MASK : cv::GC_INIT_WITH_RECT);
  cv::Mat fg_small = (labels == cv::GC_FGD) | (labels == cv::GC_PR_FGD);
  cv::Mat fg_region;
  cv::resize(fg_small, fg_region, region.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat object = fg_region(cv::Rect(box_rect.tl() - region.tl(), box_rect.size())).clone();
  if (cv::countNonZero(object) < options_.min_foreground_fraction * box_rect.area()) {
    ++fallbacks_;
    return filled;
  }
  return object;
}

}  // namespace adugs::tracking

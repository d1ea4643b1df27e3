#include "tracking/eval/mask_overlap.h"

#include <stdexcept>

namespace adugs::tracking {
namespace {

void checkMasks(const cv::Mat& exact, const cv::Mat& mask) {
  if (exact.type() != CV_8UC1 || mask.type() != CV_8UC1 || exact.size() != mask.size())
    throw std::invalid_argument("maskOverlap: two CV_8UC1 masks of the same size");
}

// Counts over `roi`, where `inside` (of roi's size, or empty for all of it) is nonzero. Whether
// there is an `inside` is decided once per row, not per pixel: this runs on every frame.
MaskOverlap count(const cv::Mat& exact, const cv::Mat& mask, const cv::Rect& roi, const cv::Mat& inside) {
  MaskOverlap o;
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const uint8_t* e = exact.ptr<uint8_t>(y) + roi.x;
    const uint8_t* m = mask.ptr<uint8_t>(y) + roi.x;
    const uint8_t* in = inside.empty() ? nullptr : inside.ptr<uint8_t>(y - roi.y);
    int n_exact = 0, n_masked = 0, n_covered = 0;
    const auto add = [&](int x, int keep) {
      const int is_exact = keep & (e[x] != 0), is_masked = keep & (m[x] != 0);
      n_exact += is_exact;
      n_masked += is_masked;
      n_covered += is_exact & is_masked;
    };
    if (in == nullptr)
      for (int x = 0; x < roi.width; ++x) add(x, 1);
    else
      for (int x = 0; x < roi.width; ++x) add(x, in[x] != 0);
    o.exact += n_exact;
    o.masked += n_masked;
    o.covered += n_covered;
  }
  return o;
}

}  // namespace

MaskOverlap maskOverlap(const cv::Mat& exact, const cv::Mat& mask) {
  checkMasks(exact, mask);
  return count(exact, mask, cv::Rect(0, 0, exact.cols, exact.rows), cv::Mat());
}

MaskOverlap maskOverlapInBoxes(const cv::Mat& exact, const cv::Mat& mask, const std::vector<cv::Rect>& boxes) {
  checkMasks(exact, mask);
  const cv::Rect image(0, 0, exact.cols, exact.rows);
  std::vector<cv::Rect> clipped;
  cv::Rect all;
  for (const cv::Rect& b : boxes) {
    const cv::Rect c = b & image;
    if (c.empty()) continue;
    all = clipped.empty() ? c : (all | c);
    clipped.push_back(c);
  }
  if (clipped.empty()) return {};
  if (clipped.size() == 1) return count(exact, mask, all, cv::Mat());
  // Where the boxes overlap or leave gaps in their bounding rectangle: which pixels are in one.
  cv::Mat inside = cv::Mat::zeros(all.size(), CV_8UC1);
  for (const cv::Rect& c : clipped) inside(c - all.tl()).setTo(1);
  return count(exact, mask, all, inside);
}

}  // namespace adugs::tracking

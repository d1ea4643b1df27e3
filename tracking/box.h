#pragma once
// An axis-aligned object box in pixels, as detectors deliver and SORT tracks it:
// centre (cx, cy), width w, height h.
#include <opencv2/core.hpp>

namespace adugs::tracking {

struct Box {
  double cx = 0, cy = 0, w = 0, h = 0;

  double area() const { return w > 0 && h > 0 ? w * h : 0.0; }
  double left() const { return cx - w / 2; }
  double top() const { return cy - h / 2; }
  double right() const { return cx + w / 2; }
  double bottom() const { return cy + h / 2; }
  cv::Rect2d rect() const { return {left(), top(), w, h}; }
  static Box fromCorners(double x0, double y0, double x1, double y1) {
    return {(x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0};
  }
};

// Intersection over union, 0 for disjoint or degenerate boxes.
double intersectionOverUnion(const Box& a, const Box& b);

}  // namespace adugs::tracking

#pragma once
// Printable AprilGrid in Kalibr's look: each tag is a black square of tagSize with a
// border_bits-wide black border around the 6x6 tag36h11 data bits, and a small black square of
// side tagSpacing*tagSize sits in every gap between tag corners (so each tag corner is an
// X-junction, which cornerSubPix locates well). Tag 0 is at the bottom-left, ids row-major.
// The same list of black rectangles feeds the PNG raster and the vector PDF, so both agree.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "calib/target/aprilgrid.h"

namespace adugs::calib {

struct Rect2d {
  double x0, y0, x1, y1;  // target frame, metres, x0 < x1, y0 < y1
};

struct TargetLayout {
  std::vector<Rect2d> black;          // everything printed black
  double min_x, min_y, max_x, max_y;  // page extent (black extent plus margin), metres
  std::string caption;                // printed in the bottom margin ("" when no room)
  double caption_x = 0, caption_y = 0;  // baseline start of the caption, metres
};

// margin_m: white border around the black extent (>= 0).
TargetLayout aprilGridLayout(const AprilGrid& grid, double margin_m = 0.02);

struct RenderedTarget {
  cv::Mat image;             // CV_8UC1, 0 or 255 (no anti-aliasing)
  double px_per_m = 0;
  double min_x = 0, max_y = 0;  // page corner that maps to pixel (-0.5, -0.5)
  // Pixel coordinates (OpenCV convention: pixel centres at integers) of a target point.
  Eigen::Vector2d pixelOf(const Eigen::Vector3d& p_T) const {
    return {(p_T.x() - min_x) * px_per_m - 0.5, (max_y - p_T.y()) * px_per_m - 0.5};
  }
};

// Raster at the given resolution (dots per inch of the printed page).
RenderedTarget renderAprilGrid(const AprilGrid& grid, double dpi, double margin_m = 0.02);
// Raster with a given number of pixels per metre (for tests and synthetic images).
RenderedTarget renderAprilGridPxPerM(const AprilGrid& grid, double px_per_m, double margin_m);

// Single-page vector PDF at true physical size (1 m = 72/0.0254 pt). Throws InputError if the
// file cannot be written.
std::string aprilGridPdf(const TargetLayout& layout);
void writeAprilGridPdf(const std::string& path, const AprilGrid& grid, double margin_m = 0.02);

}  // namespace adugs::calib

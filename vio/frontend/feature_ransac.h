#pragma once
// Outlier rejection for tracked features: RANSAC on the fundamental matrix between the undistorted
// normalised points of two frames. The points are scaled by a focal length first, so the epipolar
// threshold is in pixels of an ideal (undistorted) camera - VINS-Mono's choice - and means the
// same on every part of a distorted image. OpenCV's USAC (LO-RANSAC: the best sample's inliers
// refit the model) rather than plain FM_RANSAC, whose minimal-sample model misses ~8% of true
// inliers at 0.2 px noise and a 1 px threshold (the RANSAC test); it costs ~0.1 ms more.
#include <Eigen/Core>
#include <vector>

namespace adugs::vio {

struct FundamentalRansacOptions {
  double focal_px = 460.0;    // scale of the normalised plane (mean focal length)
  double threshold_px = 1.0;  // max distance to the epipolar line, in scaled pixels
  double confidence = 0.99;
  int min_points = 8;  // fewer: everything is kept (nothing to vote with)
};

// inlier[i] = true for points consistent with the best fundamental matrix. Sizes must match
// (std::invalid_argument otherwise). A failed estimate (degenerate input) keeps every point:
// dropping all tracks would be worse than keeping a few outliers for one frame.
std::vector<bool> fundamentalInliers(const std::vector<Eigen::Vector2d>& prev_normalized,
                                     const std::vector<Eigen::Vector2d>& cur_normalized,
                                     const FundamentalRansacOptions& options);

}  // namespace adugs::vio

#pragma once
// What the front-end hands to the estimator for one frame (VINS-Mono's feature message, Basalt's
// OpticalFlowResult): the estimator depends on this, not on the tracker that produced it.
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace adugs::vio {

// The features of one frame, index-aligned.
struct FrameFeatures {
  int64_t t_ns = 0;
  std::vector<int64_t> ids;                 // stable across frames, never reused
  std::vector<cv::Point2f> pixels;          // distorted pixel positions in this image
  std::vector<cv::Point2f> prev_pixels;     // position in the previous frame (= pixels if new)
  std::vector<Eigen::Vector2d> normalized;  // undistorted normalised (x/z, y/z)
  std::vector<int> track_counts;            // frames seen, this one included (1 = new)
  std::vector<Eigen::Vector2d> velocities;  // d(normalized)/dt [1/s]; zero for new points
  size_t size() const { return ids.size(); }
};

}  // namespace adugs::vio

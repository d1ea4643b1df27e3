#pragma once
// What one image shows of the target: corners with their pixel and their 3-D target point.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace adugs::calib {

struct CornerObservation {
  int tag_id = 0;
  int corner = 0;          // Kalibr numbering: 0 bottom-left, counter-clockwise (target frame)
  Eigen::Vector2d pixel;   // OpenCV convention: pixel centres at integer coordinates
  Eigen::Vector3d point;   // target frame, metres
};

struct TargetObservation {
  int64_t t_ns = 0;
  std::string source;  // image file or CSV the observation came from (for reports)
  std::vector<CornerObservation> corners;
};

}  // namespace adugs::calib

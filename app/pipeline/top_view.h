#pragma once
// The live view's top view of the trajectory: the estimated positions seen from above (world x to
// the right, y up; the estimator's world has z along gravity), scaled to fit the panel, on a grid
// of 1-2-5 steps whose size is written in the corner; the last pose's heading (body x axis) as an
// arrow.
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "data/types.h"

namespace adugs::app {

// A BGR panel of `size`; `state` is written at the top (e.g. "tracking", "initialising").
cv::Mat drawTopView(const std::vector<data::StampedPose>& trail, cv::Size size, const std::string& state);

// The grid step (1, 2 or 5 x 10^k metres) giving at most `max_lines` lines across `span_m`.
double topViewGridStep(double span_m, int max_lines);

}  // namespace adugs::app

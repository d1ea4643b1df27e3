#pragma once
// A one-page picture of an evaluation, drawn with OpenCV: on top the x-y view (equal aspect,
// metres) of the aligned estimate over the ground truth; below, the ATE translation error over
// time with its RMSE.
#include <opencv2/core.hpp>
#include <string>

#include "vio/eval/trajectory_eval.h"

namespace adugs::vio {

struct PlotOptions {
  int width_px = 1200;
  std::string title;  // empty: "Trajectory evaluation"
};

// BGR 8-bit image.
cv::Mat renderEvalPlot(const EvalResult& result, const PlotOptions& options = {});

// Encodes by the file extension (.png if none), writes `path`.tmp and renames it over `path`.
// Throws data::InputError naming the path if encoding or writing fails.
void writeEvalPlot(const std::string& path, const EvalResult& result,
                   const PlotOptions& options = {});

}  // namespace adugs::vio

#pragma once
// Human-readable outputs of an intrinsic calibration: a text report and a residual plot.
#include <string>

#include <opencv2/core.hpp>

#include "calib/intrinsics_calibrator.h"

namespace adugs::calib {

struct ReportContext {
  std::string input;           // where the views came from
  std::string target;          // target description
  double detect_seconds = -1;  // < 0: no detection step (corner CSVs)
  int images = 0;              // images read (detection input)
  // Optional reference calibration to compare with (e.g. a published sensor.yaml).
  bool has_reference = false;
  std::string reference_name;
  PinholeCamera reference;
  double reference_rms_px = -1;  // reprojectionRmsWithFixedIntrinsics(views, reference)
  double our_rms_all_px = -1;    // the same for our result (all corners, no outlier removal)
};

std::string formatIntrinsicsReport(const IntrinsicsResult& result, const ReportContext& context);

// Every corner: "#view,t_ns,tag_id,corner,u,v,du,dv,inlier" (du, dv = projected - measured).
std::string formatResidualCsv(const IntrinsicsResult& result);

// Left: scatter of the residual vectors of all corners (inliers coloured by view, outliers as
// red crosses) with the 1/2/3-sigma circles. Right: per-view RMS bars. 8-bit BGR image.
cv::Mat renderResidualPlot(const IntrinsicsResult& result);

}  // namespace adugs::calib

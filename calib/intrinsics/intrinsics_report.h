#pragma once
// Human-readable outputs of an intrinsic calibration: a text report (with the verdict and the
// coverage), a residual plot and a coverage picture.
#include <string>

#include <opencv2/core.hpp>

#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/intrinsics/intrinsics_verdict.h"

namespace adugs::calib {

struct ReportContext {
  std::string input;           // where the views came from
  std::string target;          // target description
  double detect_seconds = -1;  // < 0: no detection step (corner CSVs)
  int images = 0;              // images read (detection input)
  // Optional reference calibration to compare with (e.g. a published sensor.yaml).
  bool has_reference = false;
  std::string reference_name;
  CalibCamera reference;
  double reference_rms_px = -1;  // reprojectionRmsWithFixedIntrinsics(views, reference)
  double our_rms_all_px = -1;    // the same for our result (all corners, no outlier removal)
};

// The report; its head (everything before "Per view") is what the command prints.
std::string formatIntrinsicsReport(const IntrinsicsResult& result,
                                   const IntrinsicsJudgement& judgement,
                                   const ReportContext& context);

// Every corner: "#view,t_ns,tag_id,corner,u,v,du,dv,inlier" (du, dv = projected - measured).
std::string formatResidualCsv(const IntrinsicsResult& result);

// Left: scatter of the residual vectors of all corners (inliers coloured by view, outliers as
// red crosses) with the 1/2/3-sigma circles. Right: per-view RMS bars. 8-bit BGR image.
cv::Mat renderResidualPlot(const IntrinsicsResult& result);

// Why a set is weak, at a glance (as Kalibr's report and OpenCV users' coverage checks): left,
// the image frame with the coverage cells (green: holds corners) and every used corner coloured
// by view; right, each view's board tilt (normal direction as tilts about the camera's x and y
// axes, circles every 15 deg); the verdict on top. 8-bit BGR image.
cv::Mat renderCoveragePlot(const IntrinsicsResult& result, const IntrinsicsJudgement& judgement);

}  // namespace adugs::calib

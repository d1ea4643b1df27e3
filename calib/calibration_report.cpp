#include "calib/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/imgproc.hpp>

#include "calib/text_format.h"

namespace adugs::calib {

std::string formatIntrinsicsReport(const IntrinsicsResult& r, const ReportContext& ctx) {
  const PinholeCamera& c = r.camera;
  std::string s = "adugs calib intrinsics\n";
  s += "  input        " + ctx.input + "\n";
  if (!ctx.target.empty()) s += "  target       " + ctx.target + "\n";
  s += strprintf("  model        pinhole-%s, %dx%d\n", data::kalibrName(c.model).c_str(), c.width,
                 c.height);
  if (ctx.detect_seconds >= 0)
    s += strprintf("  detection    %d images in %.2f s (%.1f ms/image)\n", ctx.images,
                   ctx.detect_seconds, ctx.images > 0 ? 1000 * ctx.detect_seconds / ctx.images : 0);
  s += strprintf("  views        %d given, %zu used, %d skipped (too few corners / no pose / "
                 "outliers)\n",
                 r.views_given, r.views.size(), r.views_skipped);
  s += strprintf("  corners      %d used, %d outliers removed in %d round(s)", r.corners_used,
                 r.outliers, r.outlier_rounds);
  if (r.border_excluded > 0) s += strprintf(", %d too close to the border", r.border_excluded);
  s += "\n";
  s += strprintf("  solve        %.3f s, %d Ceres iterations, initial focal %.1f px\n\n",
                 r.solve_seconds, r.iterations, r.initial_focal_px);

  static const char* kNames[2][8] = {
      {"fu", "fv", "pu", "pv", "k1", "k2", "p1", "p2"},
      {"fu", "fv", "pu", "pv", "k1", "k2", "k3", "k4"}};
  const int m = c.model == DistortionModel::kRadialTangential ? 0 : 1;
  s += "Intrinsics (1-sigma from the covariance, scaled by the residual variance)\n";
  for (int i = 0; i < 8; ++i) {
    if (r.has_sigma)
      s += strprintf("  %-3s %16.8g  +- %.3g\n", kNames[m][i], c.params[i], r.sigma[i]);
    else
      s += strprintf("  %-3s %16.8g\n", kNames[m][i], c.params[i]);
  }
  if (ctx.has_reference) {
    s += "\nCompared with " + ctx.reference_name + " (" + data::kalibrName(ctx.reference.model) +
         ")\n";
    for (int i = 0; i < 8; ++i) {
      const double ref = ctx.reference.params[i];
      if (ctx.reference.model == c.model || i < 4)
        s += strprintf("  %-3s %16.8g  reference %16.8g  diff %+.3g%s\n", kNames[m][i], c.params[i],
                       ref, i < 4 ? 100 * (c.params[i] - ref) / ref : c.params[i] - ref,
                       i < 4 ? " %" : "");
    }
    s += strprintf("  RMS on these views, poses refit, all corners: ours %.4f px, reference %.4f px\n",
                   ctx.our_rms_all_px, ctx.reference_rms_px);
  }
  s += "\nReprojection error (inliers, pixels)\n";
  s += strprintf("  rms %.4f   mean %.4f   max %.4f   std x %.4f  y %.4f\n\n", r.rms_px,
                 r.mean_px, r.max_px, r.std_px.x(), r.std_px.y());

  s += "Per view\n";
  s += strprintf("  %4s  %20s  %7s  %7s  %8s  %8s  %s\n", "#", "t [ns]", "corners", "inliers",
                 "rms [px]", "dist [m]", "source");
  for (size_t i = 0; i < r.views.size(); ++i) {
    const ViewStats& v = r.views[i];
    s += strprintf("  %4zu  %20lld  %7d  %7d  %8.4f  %8.3f  %s\n", i,
                   static_cast<long long>(v.t_ns), v.corners, v.inliers, v.rms_px,
                   v.T_C_T.translation().norm(), v.source.c_str());
  }
  // The corners that fit worst, to find bad detections.
  std::vector<const CornerResidual*> worst;
  for (const auto& cr : r.residuals) worst.push_back(&cr);
  std::sort(worst.begin(), worst.end(), [](const CornerResidual* a, const CornerResidual* b) {
    return a->residual.norm() > b->residual.norm();
  });
  s += "\nLargest corner residuals\n";
  for (size_t i = 0; i < std::min<size_t>(10, worst.size()); ++i) {
    const CornerResidual& cr = *worst[i];
    s += strprintf("  view %4d  tag %3d corner %d  at (%7.1f, %7.1f)  error %7.3f px%s\n", cr.view,
                   cr.tag_id, cr.corner, cr.pixel.x(), cr.pixel.y(), cr.residual.norm(),
                   cr.inlier ? "" : "  (outlier, removed)");
  }
  return s;
}

std::string formatResidualCsv(const IntrinsicsResult& r) {
  std::string s = "#view,t_ns,tag_id,corner,u,v,du,dv,inlier\n";
  for (const auto& c : r.residuals)
    s += strprintf("%d,%lld,%d,%d,%.4f,%.4f,%.5f,%.5f,%d\n", c.view,
                   static_cast<long long>(r.views[static_cast<size_t>(c.view)].t_ns), c.tag_id,
                   c.corner, c.pixel.x(), c.pixel.y(), c.residual.x(), c.residual.y(),
                   c.inlier ? 1 : 0);
  return s;
}

cv::Mat renderResidualPlot(const IntrinsicsResult& r) {
  const int W = 1400, H = 700, pad = 60;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  auto text = [&](const std::string& t, int x, int y, double scale = 0.5) {
    cv::putText(img, t, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, black, 1, cv::LINE_AA);
  };
  auto viewColour = [&](int view) {
    const int n = std::max<int>(1, static_cast<int>(r.views.size()));
    cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(static_cast<int>(160.0 * view / n), 220, 200)), bgr;
    cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
    const cv::Vec3b v = bgr.at<cv::Vec3b>(0, 0);
    return cv::Scalar(v[0], v[1], v[2]);
  };

  // Scatter panel (square), range set by the inliers' spread (outliers are clipped to it).
  const int side = H - 2 * pad;
  const cv::Point o(pad + side / 2, pad + side / 2);
  const double sigma = std::max(1e-3, std::sqrt(0.5 * (r.std_px.squaredNorm())));
  double range = 4 * sigma;
  for (const auto& cr : r.residuals)
    if (cr.inlier) range = std::max(range, 1.1 * cr.residual.cwiseAbs().maxCoeff());
  const double scale = (side / 2.0) / range;
  cv::rectangle(img, cv::Rect(pad, pad, side, side), black, 1);
  cv::line(img, {pad, o.y}, {pad + side, o.y}, grey, 1);
  cv::line(img, {o.x, pad}, {o.x, pad + side}, grey, 1);
  for (int k = 1; k <= 3; ++k)
    cv::circle(img, o, static_cast<int>(k * sigma * scale), grey, 1, cv::LINE_AA);
  auto toPx = [&](const Eigen::Vector2d& e) {
    const double x = std::clamp(e.x(), -range, range), y = std::clamp(e.y(), -range, range);
    return cv::Point(static_cast<int>(o.x + x * scale), static_cast<int>(o.y + y * scale));
  };
  for (const auto& cr : r.residuals)
    if (cr.inlier) cv::circle(img, toPx(cr.residual), 2, viewColour(cr.view), cv::FILLED, cv::LINE_AA);
  for (const auto& cr : r.residuals)
    if (!cr.inlier) cv::drawMarker(img, toPx(cr.residual), cv::Scalar(0, 0, 255), cv::MARKER_CROSS, 9, 2);
  text(strprintf("reprojection residuals [px]  (circles: 1, 2, 3 sigma = %.3f px)", sigma), pad, pad - 25);
  text(strprintf("%+.2f", -range), pad - 10, pad + side + 20, 0.45);
  text(strprintf("%+.2f", range), pad + side - 40, pad + side + 20, 0.45);
  text(strprintf("rms %.3f px, %d corners, %d outliers (red x)", r.rms_px, r.corners_used,
                 r.outliers),
       pad, pad + side + 45);

  // Per-view RMS bars.
  const int x0 = 2 * pad + side + 20, x1 = W - pad / 2, y0 = pad, y1 = pad + side;
  cv::rectangle(img, cv::Rect(x0, y0, x1 - x0, y1 - y0), black, 1);
  double max_rms = r.rms_px;
  for (const auto& v : r.views) max_rms = std::max(max_rms, v.rms_px);
  max_rms = std::max(max_rms * 1.1, 1e-3);
  const size_t n = std::max<size_t>(1, r.views.size());
  const double bw = double(x1 - x0) / n;
  for (size_t i = 0; i < r.views.size(); ++i) {
    const int h = static_cast<int>((y1 - y0) * r.views[i].rms_px / max_rms);
    cv::rectangle(img, cv::Point(int(x0 + i * bw + 1), y1 - h),
                  cv::Point(int(x0 + (i + 1) * bw - 1), y1), viewColour(static_cast<int>(i)),
                  cv::FILLED);
  }
  const int y_rms = static_cast<int>(y1 - (y1 - y0) * r.rms_px / max_rms);
  cv::line(img, {x0, y_rms}, {x1, y_rms}, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  text(strprintf("per-view rms [px] (red: overall %.3f), %zu views", r.rms_px, r.views.size()), x0,
       pad - 25);
  text(strprintf("%.3f", max_rms), x0 + 5, y0 + 18, 0.45);
  text("0", x0 + 5, y1 - 5, 0.45);
  text("view index ->", x0, y1 + 20, 0.45);
  return img;
}

}  // namespace adugs::calib

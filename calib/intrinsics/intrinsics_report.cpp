#include "calib/intrinsics/intrinsics_report.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/imgproc.hpp>

#include "calib/text_format.h"

namespace adugs::calib {

namespace {

// Kalibr's spelling of the model: pinhole-radtan, pinhole-equidistant, omni-radtan, omni-none,
// ds, eucm.
std::string kalibrModel(const CalibCamera& c) {
  if (c.projection == ProjectionModel::kPinhole || c.projection == ProjectionModel::kUnified)
    return (c.projection == ProjectionModel::kPinhole ? "pinhole-" : "omni-") + data::kalibrName(c.model);
  return data::toString(c.projection);
}

// The parameters in Kalibr's order: the projection's, fu fv pu pv, the distortion's.
std::vector<int> reportOrder(const CalibCamera& c) {
  std::vector<int> order;
  for (int i : {8, 9, 0, 1, 2, 3, 4, 5, 6, 7})
    if (c.hasParameter(i)) order.push_back(i);
  return order;
}

cv::Scalar viewColour(int view, int views) {
  const int n = std::max(1, views);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(static_cast<int>(160.0 * view / n), 220, 200)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b v = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(v[0], v[1], v[2]);
}

}  // namespace

std::string formatIntrinsicsReport(const IntrinsicsResult& r, const IntrinsicsJudgement& j,
                                   const ReportContext& ctx) {
  const CalibCamera& c = r.camera;
  std::string s = "adugs calib intrinsics\n";
  s += "  input        " + ctx.input + "\n";
  if (!ctx.target.empty()) s += "  target       " + ctx.target + "\n";
  s += strprintf("  model        %s, %dx%d\n", kalibrModel(c).c_str(), c.width, c.height);
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
  s += strprintf("  start        focal %.1f px, k1 %.3g (%d candidates scored on %d views, %.2f s)\n",
                 r.initial_focal_px, r.focal_start.first_distortion, r.focal_start.candidates_scored,
                 r.focal_start.views_scored, r.start_seconds);
  if (c.projection != ProjectionModel::kPinhole && !r.stages.empty()) {
    // The projection's start: the on-axis focal length above, then stage 1 frees the first one.
    std::string q;
    for (int i : {8, 9})
      if (c.hasParameter(i)) q += strprintf(" %s %.3g", c.parameterName(i).c_str(), r.start_camera.parameter(i));
    s += strprintf("               %s:%s, fu %.1f px\n", data::toString(c.projection).c_str(), q.c_str(),
                   r.start_camera.fu());
  }
  s += strprintf("  solve        %.3f s, %d solves, %d Ceres iterations\n\n", r.solve_seconds,
                 r.solves, r.iterations);
  s += formatVerdict(j.verdict, "camchain.yaml / camera.xml") + "\n";

  s += "Intrinsics (1-sigma from the covariance, scaled by the residual variance; the formal\n"
       "1-sigma assumes independent corners and a right model: on real data the error is several\n"
       "times larger)\n";
  for (int i : reportOrder(c)) {
    const size_t k = static_cast<size_t>(i);
    std::string line = strprintf("  %-5s %16.8g", c.parameterName(i).c_str(), c.parameter(i));
    if (r.has_sigma) {
      line += strprintf("  +- %-10.3g", r.sigma[k]);
      if (i < 4) line += strprintf(" (%.2f %%)", 100 * r.sigma[k] / (i < 2 ? std::abs(c.params[k]) : c.width));
      else line += strprintf(" (%.2f px at the farthest corner, alone)", j.sigma_effect_px[k]);
    }
    if (j.poorly_determined[k]) line += "  <- poorly determined";
    s += line + "\n";
  }
  if (c.projection == ProjectionModel::kUnified || c.projection == ProjectionModel::kDoubleSphere) {
    // What the corners fix: xi and fu trade along a valley, the focal length on the axis stays.
    const DeterminedFocal fu = determinedFocal(r, 0), fv = determinedFocal(r, 1);
    s += strprintf("  on the optical axis (what the views fix; xi and fu trade along a valley): %s %.2f "
                   "+- %.3g, %s %.2f +- %.3g px\n",
                   fu.name.c_str(), fu.px, fu.sigma_px, fv.name.c_str(), fv.px, fv.sigma_px);
  }
  if (r.has_sigma)
    s += strprintf("  %s together: 1-sigma %.2f px at the farthest corner the views cover\n",
                   c.projection == ProjectionModel::kPinhole ? "distortion, all coefficients"
                   : c.model == DistortionModel::kNone       ? "projection parameters"
                                                             : "projection and distortion parameters",
                   j.distortion_sigma_px);
  if (r.camera_all_corners.width > 0 && r.outliers > 0)
    s += strprintf("  without the outlier rejection (all %d corners): fu %.2f (%+.2f %%), fv %.2f, "
                   "pu %.2f, pv %.2f\n",
                   r.corners_used + r.outliers, r.camera_all_corners.params[0],
                   100 * (r.camera_all_corners.params[0] - c.params[0]) / c.params[0],
                   r.camera_all_corners.params[1], r.camera_all_corners.params[2],
                   r.camera_all_corners.params[3]);

  const IntrinsicsCoverage& cov = j.coverage;
  s += strprintf("\nCoverage (coverage.png): the corners reach %.0f %% of the image (%dx%d cells; # = "
                 "holds corners)\n",
                 100 * cov.image_share, cov.cells_x, cov.cells_y);
  for (int y = 0; y < cov.cells_y; ++y) {
    s += "    ";
    for (int x = 0; x < cov.cells_x; ++x)
      s += cov.corners_per_cell[static_cast<size_t>(y * cov.cells_x + x)] > 0 ? '#' : '.';
    s += "\n";
  }
  if (!cov.view_tilt_deg.empty())
    s += strprintf("  board tilt %.1f..%.1f deg from face-on; the board normals span %.1f deg\n",
                   *std::min_element(cov.view_tilt_deg.begin(), cov.view_tilt_deg.end()),
                   cov.max_tilt_deg, cov.tilt_spread_deg);
  if (ctx.has_reference) {
    s += "\nCompared with " + ctx.reference_name + " (" + kalibrModel(ctx.reference) + ")\n";
    const bool same_projection = ctx.reference.projection == c.projection;
    for (int i : reportOrder(c)) {
      const bool comparable = i < 4 || (i >= 8 ? same_projection : same_projection && ctx.reference.model == c.model);
      if (!comparable) continue;
      const double ours = c.parameter(i), ref = ctx.reference.parameter(i);
      s += strprintf("  %-5s %16.8g  reference %16.8g  diff %+.3g%s\n", c.parameterName(i).c_str(), ours,
                     ref, i < 4 ? 100 * (ours - ref) / ref : ours - ref, i < 4 ? " %" : "");
    }
    s += strprintf("  RMS on these views, poses refit, all corners: ours %.4f px, reference %.4f px\n",
                   ctx.our_rms_all_px, ctx.reference_rms_px);
  }
  s += "\nReprojection error (inliers, pixels)\n";
  s += strprintf("  rms %.4f   mean %.4f   max %.4f   std x %.4f  y %.4f\n\n", r.rms_px,
                 r.mean_px, r.max_px, r.std_px.x(), r.std_px.y());

  s += "Per view\n";
  s += strprintf("  %4s  %20s  %7s  %7s  %8s  %8s  %8s  %s\n", "#", "t [ns]", "corners", "inliers",
                 "rms [px]", "dist [m]", "tilt [deg]", "source");
  for (size_t i = 0; i < r.views.size(); ++i) {
    const ViewStats& v = r.views[i];
    s += strprintf("  %4zu  %20lld  %7d  %7d  %8.4f  %8.3f  %8.1f  %s\n", i,
                   static_cast<long long>(v.t_ns), v.corners, v.inliers, v.rms_px,
                   v.T_C_T.translation().norm(), i < cov.view_tilt_deg.size() ? cov.view_tilt_deg[i] : 0.0,
                   v.source.c_str());
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
  const int views = static_cast<int>(r.views.size());

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
    if (cr.inlier) cv::circle(img, toPx(cr.residual), 2, viewColour(cr.view, views), cv::FILLED, cv::LINE_AA);
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
                  cv::Point(int(x0 + (i + 1) * bw - 1), y1), viewColour(static_cast<int>(i), views),
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

cv::Mat renderCoveragePlot(const IntrinsicsResult& r, const IntrinsicsJudgement& j) {
  const IntrinsicsCoverage& cov = j.coverage;
  const int pad = 50, top = 90, panel_w = 800, panel_h = 560;
  const int cam_w = std::max(1, r.camera.width), cam_h = std::max(1, r.camera.height);
  const double scale = std::min(double(panel_w) / cam_w, double(panel_h) / cam_h);
  const int iw = static_cast<int>(cam_w * scale), ih = static_cast<int>(cam_h * scale);
  const int disc = panel_h / 2 - 10;
  const int W = pad + iw + 2 * pad + 2 * disc + pad, H = top + std::max(ih, 2 * disc) + 70;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(170, 170, 170);
  auto text = [&](const std::string& t, int x, int y, double size = 0.5, cv::Scalar colour = cv::Scalar(0, 0, 0)) {
    cv::putText(img, t, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, size, colour, 1, cv::LINE_AA);
  };
  const Verdict verdict = j.verdict.verdict;
  const cv::Scalar verdict_colour = verdict == Verdict::kOk     ? cv::Scalar(40, 150, 40)
                                    : verdict == Verdict::kWeak ? cv::Scalar(0, 140, 255)
                                                                : cv::Scalar(0, 0, 220);
  std::string checks;
  for (const VerdictFinding& f : j.verdict.findings)
    if (checks.find(f.check) == std::string::npos) checks += (checks.empty() ? "" : ", ") + f.check;
  text(strprintf("verdict: %s%s%s", verdictName(verdict), checks.empty() ? "" : "  (", checks.empty() ? "" : (checks + ")").c_str()),
       pad, 35, 0.8, verdict_colour);

  // Image frame with the coverage cells and the corners.
  const cv::Point o(pad, top);
  for (int y = 0; y < cov.cells_y; ++y)
    for (int x = 0; x < cov.cells_x; ++x) {
      const cv::Rect cell(o.x + iw * x / cov.cells_x, o.y + ih * y / cov.cells_y,
                          iw * (x + 1) / cov.cells_x - iw * x / cov.cells_x,
                          ih * (y + 1) / cov.cells_y - ih * y / cov.cells_y);
      const bool covered = cov.corners_per_cell[static_cast<size_t>(y * cov.cells_x + x)] > 0;
      cv::rectangle(img, cell, covered ? cv::Scalar(200, 240, 200) : cv::Scalar(225, 225, 245), cv::FILLED);
      cv::rectangle(img, cell, grey, 1);
    }
  const int views = static_cast<int>(r.views.size());
  for (const CornerResidual& cr : r.residuals) {
    if (!cr.inlier) continue;
    const cv::Point p(o.x + static_cast<int>(cr.pixel.x() * scale), o.y + static_cast<int>(cr.pixel.y() * scale));
    cv::circle(img, p, 1, viewColour(cr.view, views), cv::FILLED, cv::LINE_AA);
  }
  cv::rectangle(img, cv::Rect(o.x, o.y, iw, ih), black, 2);
  text(strprintf("corners of %d views over the %dx%d image: %.0f %% of the cells covered", views,
                 r.camera.width, r.camera.height, 100 * cov.image_share),
       o.x, o.y - 12);

  // Tilt disc: each view's board normal as tilts about the camera's y (right) and x (down) axes.
  const cv::Point c(o.x + iw + 2 * pad + disc, top + disc);
  const double max_deg = 60;
  for (int deg = 15; deg <= 60; deg += 15) {
    cv::circle(img, c, static_cast<int>(disc * deg / max_deg), grey, 1, cv::LINE_AA);
    text(std::to_string(deg), c.x + static_cast<int>(disc * deg / max_deg) + 2, c.y - 3, 0.4, grey);
  }
  cv::line(img, {c.x - disc, c.y}, {c.x + disc, c.y}, grey, 1);
  cv::line(img, {c.x, c.y - disc}, {c.x, c.y + disc}, grey, 1);
  for (size_t i = 0; i < cov.view_tilt_xy_deg.size(); ++i) {
    const Eigen::Vector2d t = cov.view_tilt_xy_deg[i];
    const double x = std::clamp(t.y(), -max_deg, max_deg), y = std::clamp(t.x(), -max_deg, max_deg);
    cv::circle(img, cv::Point(c.x + static_cast<int>(disc * x / max_deg), c.y + static_cast<int>(disc * y / max_deg)),
               4, viewColour(static_cast<int>(i), views), cv::FILLED, cv::LINE_AA);
  }
  text("board tilt per view [deg] (about the camera's y: right, x: down)", c.x - disc, top - 12);
  text(strprintf("tilt %.1f..%.1f deg, normals span %.1f deg",
                 cov.view_tilt_deg.empty() ? 0.0 : *std::min_element(cov.view_tilt_deg.begin(), cov.view_tilt_deg.end()),
                 cov.max_tilt_deg, cov.tilt_spread_deg),
       c.x - disc, top + 2 * disc + 30);
  text("colours: view index (first red ... last blue-violet)", pad, H - 15, 0.45);
  return img;
}

}  // namespace adugs::calib

#include "vio/eval/trajectory_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "data/formats/atomic_file.h"
#include "data/formats/image_file.h"
#include "data/input_error.h"

namespace adugs::vio {
namespace {

// Colours (BGR), close to matplotlib's defaults.
const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(225, 225, 225);
const cv::Scalar kFrame(150, 150, 150);
const cv::Scalar kGroundTruth(70, 70, 70);
const cv::Scalar kEstimate(180, 119, 31);  // blue
const cv::Scalar kRmse(40, 39, 214);       // red
const cv::Scalar kStart(44, 160, 44);      // green
const cv::Scalar kEnd(14, 127, 255);       // orange
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// A linear map from data [lo, hi] to pixels [px_lo, px_hi] (px_hi < px_lo for a y axis).
struct Axis {
  double lo, hi;
  int px_lo, px_hi;
  double toPx(double v) const { return px_lo + (v - lo) / (hi - lo) * (px_hi - px_lo); }
};

double niceStep(double range, int target_ticks) {
  const double raw = range / std::max(1, target_ticks);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / magnitude;
  return (f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0) * magnitude;
}

std::string tickLabel(double v, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point org, double scale, const cv::Scalar& color,
          int thickness = 1) {
  cv::putText(img, s, org, kFont, scale, color, thickness, cv::LINE_AA);
}

cv::Size textSize(const std::string& s, double scale, int thickness = 1) {
  int baseline = 0;
  return cv::getTextSize(s, kFont, scale, thickness, &baseline);
}

// Text rotated 90 degrees counter-clockwise, centred on `centre`.
void verticalText(cv::Mat& img, const std::string& s, cv::Point centre, double scale) {
  cv::Size size = textSize(s, scale);
  cv::Mat patch(size.height + 8, size.width + 4, img.type(), kWhite);
  text(patch, s, {2, size.height + 2}, scale, kInk);
  cv::rotate(patch, patch, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect roi(centre.x - patch.cols / 2, centre.y - patch.rows / 2, patch.cols, patch.rows);
  roi &= cv::Rect(0, 0, img.cols, img.rows);
  patch(cv::Rect(0, 0, roi.width, roi.height)).copyTo(img(roi));
}

void dashedLine(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& color,
                int thickness) {
  const double length = cv::norm(b - a);
  const double dash = 10.0, gap = 6.0;
  for (double s = 0.0; s < length; s += dash + gap) {
    cv::Point2d p = a + (b - a) * (s / length);
    cv::Point2d q = a + (b - a) * (std::min(s + dash, length) / length);
    cv::line(img, p, q, color, thickness, cv::LINE_AA);
  }
}

// Grid lines, tick labels and frame of a panel; returns nothing, draws in place.
void drawAxes(cv::Mat& img, const cv::Rect& box, const Axis& x, const Axis& y,
              const std::string& x_label, const std::string& y_label) {
  const double font = 0.5;
  const double x_step = niceStep(x.hi - x.lo, std::max(3, box.width / 110));
  const double y_step = niceStep(y.hi - y.lo, std::max(3, box.height / 70));
  for (double v = std::ceil(x.lo / x_step) * x_step; v <= x.hi + 1e-9 * x_step; v += x_step) {
    int px = static_cast<int>(std::lround(x.toPx(v)));
    cv::line(img, {px, box.y}, {px, box.y + box.height}, kGrid, 1);
    cv::line(img, {px, box.y + box.height}, {px, box.y + box.height + 5}, kFrame, 1);
    std::string label = tickLabel(v, x_step);
    cv::Size s = textSize(label, font);
    text(img, label, {px - s.width / 2, box.y + box.height + 10 + s.height}, font, kInk);
  }
  int max_label_width = 0;
  for (double v = std::ceil(y.lo / y_step) * y_step; v <= y.hi + 1e-9 * y_step; v += y_step) {
    int py = static_cast<int>(std::lround(y.toPx(v)));
    cv::line(img, {box.x, py}, {box.x + box.width, py}, kGrid, 1);
    cv::line(img, {box.x - 5, py}, {box.x, py}, kFrame, 1);
    std::string label = tickLabel(v, y_step);
    cv::Size s = textSize(label, font);
    max_label_width = std::max(max_label_width, s.width);
    text(img, label, {box.x - 9 - s.width, py + s.height / 2}, font, kInk);
  }
  cv::rectangle(img, box, kFrame, 1);
  cv::Size xs = textSize(x_label, 0.55);
  text(img, x_label, {box.x + box.width / 2 - xs.width / 2, box.y + box.height + 48}, 0.55, kInk);
  verticalText(img, y_label, {box.x - 24 - max_label_width, box.y + box.height / 2}, 0.55);
}

void polyline(cv::Mat& img, const std::vector<cv::Point2d>& points, const cv::Scalar& color,
              int thickness) {
  std::vector<cv::Point> px;  // fixed point with 4 fractional bits for smooth anti-aliased lines
  px.reserve(points.size());
  for (const cv::Point2d& p : points)
    px.emplace_back(static_cast<int>(std::lround(p.x * 16)),
                    static_cast<int>(std::lround(p.y * 16)));
  cv::polylines(img, px, false, color, thickness, cv::LINE_AA, 4);
}

struct LegendEntry {
  std::string label;
  cv::Scalar color;
  enum Kind { kLine, kDashed, kDot, kSquare } kind;
};

// One row of legend entries, right-aligned at `right`, centred vertically on `y`. Sits outside
// the panels so that it never hides data.
void drawLegendRow(cv::Mat& img, int right, int y, const std::vector<LegendEntry>& entries) {
  const double font = 0.5;
  const int symbol = 30, gap = 8, spacing = 26;
  int width = 0;
  for (const LegendEntry& e : entries)
    width += symbol + gap + textSize(e.label, font).width + spacing;
  int x = right - width + spacing;
  for (const LegendEntry& e : entries) {
    const cv::Point centre(x + symbol / 2, y);
    switch (e.kind) {
      case LegendEntry::kLine:
        cv::line(img, {x, y}, {x + symbol, y}, e.color, 2, cv::LINE_AA);
        break;
      case LegendEntry::kDashed:
        dashedLine(img, {double(x), double(y)}, {double(x + symbol), double(y)}, e.color, 2);
        break;
      case LegendEntry::kDot:
        cv::circle(img, centre, 6, e.color, cv::FILLED, cv::LINE_AA);
        break;
      case LegendEntry::kSquare:
        cv::rectangle(img, cv::Rect(centre.x - 5, y - 5, 11, 11), e.color, cv::FILLED);
        break;
    }
    x += symbol + gap;
    const cv::Size s = textSize(e.label, font);
    text(img, e.label, {x, y + s.height / 2}, font, kInk);
    x += s.width + spacing;
  }
}

// The x-y extent of both trajectories.
struct Bounds {
  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  double width() const { return std::max(x_hi - x_lo, 1e-3); }
  double height() const { return std::max(y_hi - y_lo, 1e-3); }
};

Bounds xyBounds(const EvalResult& r) {
  Bounds b;
  for (const data::Trajectory* t : {&r.gt_matched, &r.est_aligned}) {
    for (const data::StampedPose& p : *t) {
      b.x_lo = std::min(b.x_lo, p.p_W_B.x());
      b.x_hi = std::max(b.x_hi, p.p_W_B.x());
      b.y_lo = std::min(b.y_lo, p.p_W_B.y());
      b.y_hi = std::max(b.y_hi, p.p_W_B.y());
    }
  }
  return b;
}

void drawTopView(cv::Mat& img, const cv::Rect& box, const EvalResult& r) {
  // Equal aspect: one metre is the same number of pixels on both axes; 8 % padding.
  const Bounds b = xyBounds(r);
  const double px_per_m = std::min(box.width / b.width(), box.height / b.height()) / 1.08;
  const double half_w = 0.5 * box.width / px_per_m, half_h = 0.5 * box.height / px_per_m;
  const double cx = 0.5 * (b.x_lo + b.x_hi), cy = 0.5 * (b.y_lo + b.y_hi);
  Axis ax{cx - half_w, cx + half_w, box.x, box.x + box.width};
  Axis ay{cy - half_h, cy + half_h, box.y + box.height, box.y};
  drawAxes(img, box, ax, ay, "x [m]", "y [m]");

  auto toPx = [&](const data::StampedPose& p) {
    return cv::Point2d(ax.toPx(p.p_W_B.x()), ay.toPx(p.p_W_B.y()));
  };
  std::vector<cv::Point2d> gt, est;
  for (const data::StampedPose& p : r.gt_matched) gt.push_back(toPx(p));
  for (const data::StampedPose& p : r.est_aligned) est.push_back(toPx(p));
  polyline(img, gt, kGroundTruth, 2);
  polyline(img, est, kEstimate, est.size() > static_cast<size_t>(box.width) ? 1 : 2);
  cv::circle(img, gt.front(), 7, kStart, cv::FILLED, cv::LINE_AA);
  cv::rectangle(img, cv::Rect(cv::Point(gt.back()) - cv::Point(5, 5), cv::Size(11, 11)), kEnd,
                cv::FILLED);

  const std::string est_label =
      std::string("estimate (") + alignModeName(r.align_mode) + " aligned)";
  drawLegendRow(img, box.x + box.width, box.y - 16,
                {{"ground truth", kGroundTruth, LegendEntry::kLine},
                 {est_label, kEstimate, LegendEntry::kLine},
                 {"start", kStart, LegendEntry::kDot},
                 {"end", kEnd, LegendEntry::kSquare}});
}

void drawErrorOverTime(cv::Mat& img, const cv::Rect& box, const EvalResult& r) {
  const AteResult& ate = r.ate;
  const double t0 = data::nsToSec(ate.t_ns.front());
  const double duration = std::max(data::nsToSec(ate.t_ns.back()) - t0, 1e-3);
  const double e_max = std::max(ate.translation.max, 1e-6) * 1.1;
  Axis ax{0.0, duration, box.x, box.x + box.width};
  Axis ay{0.0, e_max, box.y + box.height, box.y};
  drawAxes(img, box, ax, ay, "time since first matched pose [s]", "error [m]");

  std::vector<cv::Point2d> curve;
  for (size_t i = 0; i < ate.t_ns.size(); ++i)
    curve.emplace_back(ax.toPx(data::nsToSec(ate.t_ns[i]) - t0), ay.toPx(ate.translation_m[i]));
  polyline(img, curve, kEstimate, curve.size() > static_cast<size_t>(box.width) / 2 ? 1 : 2);
  const double y = ay.toPx(ate.translation.rmse);
  dashedLine(img, {double(box.x), y}, {double(box.x + box.width), y}, kRmse, 2);

  char rmse[64];
  std::snprintf(rmse, sizeof(rmse), "RMSE %.4g m", ate.translation.rmse);
  text(img, "Absolute translation error over time", {box.x, box.y - 10}, 0.6, kInk);
  drawLegendRow(
      img, box.x + box.width, box.y - 16,
      {{"translation error", kEstimate, LegendEntry::kLine}, {rmse, kRmse, LegendEntry::kDashed}});
}

}  // namespace

cv::Mat renderEvalPlot(const EvalResult& result, const PlotOptions& options) {
  if (result.ate.t_ns.empty()) throw std::invalid_argument("renderEvalPlot: empty evaluation");
  const int W = std::max(600, options.width_px);
  const int left = 110, right = 40, title_h = 110, axis_h = 66, gap_h = 50;
  const int plot_w = W - left - right;
  // The top view takes the data's aspect ratio, within limits.
  const Bounds b = xyBounds(result);
  const int top_h =
      static_cast<int>(std::clamp(plot_w * b.height() / b.width(), 0.45 * plot_w, 0.9 * plot_w));
  const int bottom_h = static_cast<int>(0.22 * W);
  const int H = title_h + top_h + axis_h + gap_h + bottom_h + axis_h;
  cv::Mat img(H, W, CV_8UC3, kWhite);

  const std::string title = options.title.empty() ? "Trajectory evaluation" : options.title;
  text(img, title, {left, 38}, 0.8, kInk, 2);
  char summary[200];
  std::snprintf(summary, sizeof(summary),
                "%zu matched poses, %s alignment, ground-truth length %.2f m, ATE RMSE %.4g m",
                result.pairs.size(), alignModeName(result.align_mode), result.gt_length_m,
                result.ate.translation.rmse);
  text(img, summary, {left, 66}, 0.5, kInk);

  drawTopView(img, cv::Rect(left, title_h, plot_w, top_h), result);
  drawErrorOverTime(img, cv::Rect(left, title_h + top_h + axis_h + gap_h, plot_w, bottom_h),
                    result);
  return img;
}

void writeEvalPlot(const std::string& path, const EvalResult& result, const PlotOptions& options) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (ext.empty()) ext = ".png";
  const std::vector<uint8_t> bytes = data::encodeImage(ext, renderEvalPlot(result, options), path);
  data::writeTextFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace adugs::vio

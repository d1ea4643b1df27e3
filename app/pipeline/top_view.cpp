#include "app/pipeline/top_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace adugs::app {

double topViewGridStep(double span_m, int max_lines) {
  const double raw = span_m / std::max(1, max_lines);
  const double decade = std::pow(10.0, std::floor(std::log10(std::max(raw, 1e-9))));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= raw) return m * decade;
  return 10.0 * decade;
}

cv::Mat drawTopView(const std::vector<data::StampedPose>& trail, cv::Size size, const std::string& state) {
  cv::Mat panel(size, CV_8UC3, cv::Scalar(30, 30, 30));
  const int margin = 24;
  const int usable = std::max(10, std::min(size.width, size.height) - 2 * margin);
  // The square around every position so far (at least 1 m across), centred in the panel.
  Eigen::Vector2d lo(0, 0), hi(0, 0);
  if (!trail.empty()) {
    lo = hi = trail.front().p_W_B.head<2>();
    for (const data::StampedPose& p : trail) {
      lo = lo.cwiseMin(p.p_W_B.head<2>());
      hi = hi.cwiseMax(p.p_W_B.head<2>());
    }
  }
  const double span = std::max(1.0, (hi - lo).maxCoeff());
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  const double scale = usable / span;  // px per metre
  const auto toPixel = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(size.width / 2.0 + (p.x() - centre.x()) * scale)),
                     static_cast<int>(std::lround(size.height / 2.0 - (p.y() - centre.y()) * scale)));
  };
  // Grid lines on multiples of the step.
  const double step = topViewGridStep(span * std::max(size.width, size.height) / usable, 8);
  const double half_w = 0.5 * size.width / scale, half_h = 0.5 * size.height / scale;
  for (double x = std::ceil((centre.x() - half_w) / step) * step; x <= centre.x() + half_w; x += step) {
    const int u = toPixel({x, centre.y()}).x;
    cv::line(panel, {u, 0}, {u, size.height - 1}, cv::Scalar(60, 60, 60), 1);
  }
  for (double y = std::ceil((centre.y() - half_h) / step) * step; y <= centre.y() + half_h; y += step) {
    const int v = toPixel({centre.x(), y}).y;
    cv::line(panel, {0, v}, {size.width - 1, v}, cv::Scalar(60, 60, 60), 1);
  }
  for (size_t i = 1; i < trail.size(); ++i)
    cv::line(panel, toPixel(trail[i - 1].p_W_B.head<2>()), toPixel(trail[i].p_W_B.head<2>()),
             cv::Scalar(0, 200, 255), 2, cv::LINE_AA);
  if (!trail.empty()) {
    const data::StampedPose& last = trail.back();
    const cv::Point at = toPixel(last.p_W_B.head<2>());
    cv::circle(panel, at, 5, cv::Scalar(0, 255, 0), cv::FILLED);
    Eigen::Vector2d heading = (last.q_W_B * Eigen::Vector3d::UnitX()).head<2>();
    if (heading.norm() > 1e-6) {
      heading.normalize();
      const cv::Point tip(at.x + static_cast<int>(std::lround(20 * heading.x())),
                          at.y - static_cast<int>(std::lround(20 * heading.y())));
      cv::arrowedLine(panel, at, tip, cv::Scalar(0, 255, 0), 2, cv::LINE_AA, 0, 0.3);
    }
  }
  char label[96];
  std::snprintf(label, sizeof label, "top view, grid %g m", step);
  cv::putText(panel, label, {8, size.height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(200, 200, 200), 1);
  cv::putText(panel, state, {8, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1);
  return panel;
}

}  // namespace adugs::app

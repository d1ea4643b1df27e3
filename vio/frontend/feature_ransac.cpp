#include "vio/frontend/feature_ransac.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace adugs::vio {

std::vector<bool> fundamentalInliers(const std::vector<Eigen::Vector2d>& prev,
                                     const std::vector<Eigen::Vector2d>& cur,
                                     const FundamentalRansacOptions& o) {
  if (prev.size() != cur.size())
    throw std::invalid_argument("fundamentalInliers: point lists differ in size");
  std::vector<bool> inlier(prev.size(), true);
  if (static_cast<int>(prev.size()) < std::max(8, o.min_points)) return inlier;

  std::vector<cv::Point2f> a(prev.size()), b(cur.size());
  for (size_t i = 0; i < prev.size(); ++i) {
    a[i] = cv::Point2f(static_cast<float>(o.focal_px * prev[i].x()),
                       static_cast<float>(o.focal_px * prev[i].y()));
    b[i] = cv::Point2f(static_cast<float>(o.focal_px * cur[i].x()),
                       static_cast<float>(o.focal_px * cur[i].y()));
  }
  std::vector<uchar> status;
  const cv::Mat F =
      cv::findFundamentalMat(a, b, cv::USAC_DEFAULT, o.threshold_px, o.confidence, status);
  if (F.empty() || status.size() != prev.size()) return inlier;
  for (size_t i = 0; i < status.size(); ++i) inlier[i] = status[i] != 0;
  return inlier;
}

}  // namespace adugs::vio

#include "calib/intrinsics/intrinsics_problem.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>

namespace adugs::calib {

bool poseFromPnp(const TargetObservation& view, double f, double cu, double cv, Pose6& pose) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto& c : view.corners) {
    object.emplace_back(c.point.x(), c.point.y(), c.point.z());
    image.emplace_back(c.pixel.x(), c.pixel.y());
  }
  if (object.size() < 4) return false;
  const cv::Mat K = (cv::Mat_<double>(3, 3) << f, 0, cu, 0, f, cv, 0, 0, 1);
  const bool planar = std::all_of(view.corners.begin(), view.corners.end(),
                                  [](const CornerObservation& c) { return std::abs(c.point.z()) < 1e-9; });
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, image, K, cv::noArray(), rvec, tvec, false,
                      planar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_ITERATIVE))
      return false;
  } catch (const cv::Exception&) {
    return false;
  }
  if (!(tvec.at<double>(2) > 0)) return false;
  for (int i = 0; i < 3; ++i) {
    pose[i] = rvec.at<double>(i);
    pose[3 + i] = tvec.at<double>(i);
  }
  return std::all_of(pose.begin(), pose.end(), [](double x) { return std::isfinite(x); });
}

Eigen::Vector2d cornerResidual(const CalibCamera& camera, const Pose6& pose,
                               const CornerObservation& corner) {
  const ReprojectionCost cost(camera.projection, camera.model, corner.pixel, corner.point);
  Eigen::Vector2d r;
  if (!cost(camera.params.data(), camera.params.data() + 2, camera.projection_params.data(),
            camera.params.data() + 4, pose.data(), r.data()))
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return r;
}

}  // namespace adugs::calib

#include "data/sim_camera.h"

#include <cmath>

#include <Eigen/Dense>

#include "data/input_error.h"

namespace adugs::data {

Eigen::Vector2d SimCamera::distort(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

Eigen::Vector2d SimCamera::undistort(const Eigen::Vector2d& xy_distorted) const {
  if (!hasDistortion()) return xy_distorted;
  // Fixed-point start, then Gauss-Newton on distort(x) = target with the analytic Jacobian:
  // converges to machine precision in a few steps for EuRoC-like lenses.
  Eigen::Vector2d xy = xy_distorted;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d err = distort(xy) - xy_distorted;
    if (err.squaredNorm() < 1e-26) break;
    const double x = xy.x(), y = xy.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
    const double dradial = 2.0 * k1 + 4.0 * k2 * r2;  // d radial / d(r2) * 2
    Eigen::Matrix2d J;
    J(0, 0) = radial + x * dradial * x + 2.0 * p1 * y + 6.0 * p2 * x;
    J(0, 1) = x * dradial * y + 2.0 * p1 * x + 2.0 * p2 * y;
    J(1, 0) = y * dradial * x + 2.0 * p1 * x + 2.0 * p2 * y;
    J(1, 1) = radial + y * dradial * y + 6.0 * p1 * y + 2.0 * p2 * x;
    xy -= J.inverse() * err;
  }
  return xy;
}

bool SimCamera::project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const {
  if (p_C.z() <= 1e-9) return false;
  const Eigen::Vector2d d = distort(p_C.head<2>() / p_C.z());
  *uv = {fx * d.x() + cx, fy * d.y() + cy};
  return true;
}

Eigen::Vector3d SimCamera::unproject(const Eigen::Vector2d& uv) const {
  const Eigen::Vector2d xy = undistort({(uv.x() - cx) / fx, (uv.y() - cy) / fy});
  return {xy.x(), xy.y(), 1.0};
}

SimCamera SimCamera::scaled(double s) const {
  SimCamera c = *this;
  c.width = static_cast<int>(std::lround(width * s));
  c.height = static_cast<int>(std::lround(height * s));
  c.fx = fx * s;
  c.fy = fy * s;
  // Pixel centres: u' + 0.5 = s (u + 0.5).
  c.cx = (cx + 0.5) * s - 0.5;
  c.cy = (cy + 0.5) * s - 0.5;
  return c;
}

SimCamera simCameraFromCalibration(const CameraCalibration& calib, const std::string& source) {
  if (calib.distortion_model != DistortionModel::kRadialTangential || calib.distortion.size() != 4)
    throw InputError(source, 0, "distortion_model",
                     "the simulator renders radial-tangential cameras only (got " +
                         toString(calib.distortion_model) + ")");
  SimCamera c;
  c.width = calib.width;
  c.height = calib.height;
  c.fx = calib.fx, c.fy = calib.fy, c.cx = calib.cx, c.cy = calib.cy;
  c.k1 = calib.distortion[0], c.k2 = calib.distortion[1];
  c.p1 = calib.distortion[2], c.p2 = calib.distortion[3];
  return c;
}

CameraCalibration calibrationFromSimCamera(const SimCamera& camera,
                                           const Eigen::Isometry3d& T_B_C, double rate_hz) {
  CameraCalibration c;
  c.width = camera.width;
  c.height = camera.height;
  c.fx = camera.fx, c.fy = camera.fy, c.cx = camera.cx, c.cy = camera.cy;
  c.distortion_model = DistortionModel::kRadialTangential;
  c.distortion = {camera.k1, camera.k2, camera.p1, camera.p2};
  c.T_B_C = T_B_C;
  c.rate_hz = rate_hz;
  return c;
}

}  // namespace adugs::data

#include "calib/camera_model.h"

#include <Eigen/Dense>

namespace adugs::calib {

bool parseDistortionModel(const std::string& name, DistortionModel& out) {
  if (name == "radtan" || name == "radial-tangential" || name == "radtan4") {
    out = DistortionModel::kRadialTangential;
    return true;
  }
  if (name == "equidistant" || name == "equi" || name == "equi4" || name == "fisheye") {
    out = DistortionModel::kEquidistant;
    return true;
  }
  return false;
}

std::string kalibrName(DistortionModel model) {
  return model == DistortionModel::kRadialTangential ? "radtan" : "equidistant";
}

bool PinholeCamera::project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const {
  return projectPoint(model, params.data(), p_C.data(), uv.data());
}

bool PinholeCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const {
  const Eigen::Vector2d target((uv.x() - pu()) / fu(), (uv.y() - pv()) / fv());
  // Gauss-Newton on the distortion with a numeric Jacobian: small, and only for init/reports.
  Eigen::Vector2d x = target;
  for (int it = 0; it < 30; ++it) {
    Eigen::Vector2d f;
    distortPoint(model, params.data() + 4, x.x(), x.y(), f.x(), f.y());
    const Eigen::Vector2d r = f - target;
    if (r.norm() < 1e-12) break;
    Eigen::Matrix2d J;
    const double h = 1e-7;
    for (int j = 0; j < 2; ++j) {
      Eigen::Vector2d xh = x;
      xh[j] += h;
      Eigen::Vector2d fh;
      distortPoint(model, params.data() + 4, xh.x(), xh.y(), fh.x(), fh.y());
      J.col(j) = (fh - f) / h;
    }
    x -= J.colPivHouseholderQr().solve(r);
    if (!x.allFinite()) return false;
  }
  Eigen::Vector2d check;
  distortPoint(model, params.data() + 4, x.x(), x.y(), check.x(), check.y());
  ray = Eigen::Vector3d(x.x(), x.y(), 1.0);
  return (check - target).norm() < 1e-8;
}

data::CameraCalibration PinholeCamera::toEuroc() const {
  data::CameraCalibration c;
  c.width = width;
  c.height = height;
  c.fx = fu();
  c.fy = fv();
  c.cx = pu();
  c.cy = pv();
  c.distortion_model = model;
  c.distortion.assign(params.begin() + 4, params.end());
  return c;
}

}  // namespace adugs::calib

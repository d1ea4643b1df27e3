#include "calib/calib_camera.h"

namespace adugs::calib {

bool CalibCamera::project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const {
  return data::projectPoint(model, params.data(), p_C.data(), uv.data());
}

bool CalibCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const {
  const data::CameraModel camera = cameraModel();
  const Eigen::Vector2d xn = camera.pixelToNormalized(uv);
  // The undistortion stops just short of 90 degrees for fisheye pixels beyond it: check it hit.
  const Eigen::Vector2d target((uv.x() - pu()) / fu(), (uv.y() - pv()) / fv());
  if (!xn.allFinite() || (camera.distort(xn) - target).norm() >= 1e-8) return false;
  ray = Eigen::Vector3d(xn.x(), xn.y(), 1.0);
  return true;
}

data::CameraModel CalibCamera::cameraModel() const {
  return data::CameraModel(width, height, fu(), fv(), pu(), pv(),
                           data::CameraModel::fromModel(model),
                           {params[4], params[5], params[6], params[7]});
}

data::CameraCalibration CalibCamera::toEuroc() const {
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

#include "calib/calib_camera.h"

#include "calib/lens_refit.h"

namespace adugs::calib {

bool CalibCamera::hasParameter(int i) const {
  if (i < 0 || i >= kParameters) return false;
  if (i < 4) return true;
  if (i < 8) return model != DistortionModel::kNone;
  return i - 8 < data::projectionParameterCount(projection);
}

std::string CalibCamera::parameterName(int i) const {
  static const char* const kPinhole[4] = {"fu", "fv", "pu", "pv"};
  static const char* const kRadtan[4] = {"k1", "k2", "p1", "p2"};
  static const char* const kEquidistant[4] = {"k1", "k2", "k3", "k4"};
  if (i < 0 || i >= kParameters) return "?";
  if (i < 4) return kPinhole[i];
  if (i < 8) return (model == DistortionModel::kEquidistant ? kEquidistant : kRadtan)[i - 4];
  if (projection == ProjectionModel::kExtendedUnified) return i == 8 ? "alpha" : "beta";
  return i == 8 ? "xi" : "alpha";
}

std::string CalibCamera::modelName() const { return lensModelName(toEuroc()); }

bool CalibCamera::project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const {
  return data::projectPoint(projection, projection_params.data(), model, params.data(), p_C.data(),
                            uv.data());
}

bool CalibCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const {
  const data::CameraModel camera = cameraModel();
  if (projection != ProjectionModel::kPinhole) {
    Eigen::Vector3d unit;
    if (!camera.unproject(uv, &unit) || !(unit.z() > 1e-6)) return false;
    ray = unit / unit.z();
    return true;
  }
  const Eigen::Vector2d xn = camera.pixelToNormalized(uv);
  // The undistortion stops just short of 90 degrees for fisheye pixels beyond it: check it hit.
  const Eigen::Vector2d target((uv.x() - pu()) / fu(), (uv.y() - pv()) / fv());
  if (!xn.allFinite() || (camera.distort(xn) - target).norm() >= 1e-8) return false;
  ray = Eigen::Vector3d(xn.x(), xn.y(), 1.0);
  return true;
}

data::CameraModel CalibCamera::cameraModel() const {
  return data::CameraModel(toEuroc());
}

data::CameraCalibration CalibCamera::toEuroc() const {
  data::CameraCalibration c;
  c.width = width;
  c.height = height;
  c.fx = fu();
  c.fy = fv();
  c.cx = pu();
  c.cy = pv();
  c.projection = projection;
  c.projection_params.assign(projection_params.begin(),
                             projection_params.begin() + data::projectionParameterCount(projection));
  c.distortion_model = model;
  c.distortion.assign(params.begin() + 4, params.end());
  return c;
}

CalibCamera fromCalibration(const data::CameraCalibration& c) {
  CalibCamera cam;
  cam.width = c.width;
  cam.height = c.height;
  cam.projection = c.projection;
  cam.model = c.distortion_model;
  cam.params = {c.fx, c.fy, c.cx, c.cy, 0, 0, 0, 0};
  for (size_t i = 0; i < 4 && i < c.distortion.size(); ++i) cam.params[4 + i] = c.distortion[i];
  for (size_t i = 0; i < 2 && i < c.projection_params.size(); ++i) cam.projection_params[i] = c.projection_params[i];
  return cam;
}

}  // namespace adugs::calib

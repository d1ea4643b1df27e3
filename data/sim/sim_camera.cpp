#include "data/sim/sim_camera.h"

#include <cmath>
#include <stdexcept>

#include "data/input_error.h"

namespace adugs::data {

bool SimCamera::hasDistortion() const {
  if (projection != ProjectionModel::kPinhole) return true;
  if (distortion_model == DistortionModel::kNone) return false;
  if (distortion_model == DistortionModel::kEquidistant) return true;
  for (double k : distortion)
    if (k != 0) return true;
  return false;
}

CameraModel SimCamera::model() const {
  // Zero radtan coefficients are no distortion (the model skips the iterations).
  const bool zero_radtan = distortion_model == DistortionModel::kRadialTangential &&
                           distortion == std::array<double, 4>{};
  const CameraModel::Distortion d =
      zero_radtan ? CameraModel::Distortion::kNone : CameraModel::fromModel(distortion_model);
  return CameraModel(width, height, fx, fy, cx, cy, projection, projection_params, d, distortion);
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
  if (calib.distortion.size() != 4)
    throw InputError(source, 0, "distortion_coefficients",
                     "the simulator needs 4 distortion coefficients (got " +
                         std::to_string(calib.distortion.size()) + ")");
  SimCamera c;
  c.width = calib.width;
  c.height = calib.height;
  c.fx = calib.fx, c.fy = calib.fy, c.cx = calib.cx, c.cy = calib.cy;
  c.projection = calib.projection;
  c.projection_params = calib.projection_params;
  c.distortion_model = calib.distortion_model;
  for (size_t i = 0; i < 4; ++i) c.distortion[i] = calib.distortion[i];
  try {
    c.model();
  } catch (const std::invalid_argument& e) {
    throw InputError(source, 0, "intrinsics", e.what());
  }
  return c;
}

CameraCalibration calibrationFromSimCamera(const SimCamera& camera, const Eigen::Isometry3d& T_B_C,
                                           double rate_hz) {
  CameraCalibration c;
  c.width = camera.width;
  c.height = camera.height;
  c.fx = camera.fx, c.fy = camera.fy, c.cx = camera.cx, c.cy = camera.cy;
  c.projection = camera.projection;
  c.projection_params = camera.projection_params;
  c.distortion_model = camera.distortion_model;
  c.distortion.assign(camera.distortion.begin(), camera.distortion.end());
  c.T_B_C = T_B_C;
  c.rate_hz = rate_hz;
  return c;
}

}  // namespace adugs::data

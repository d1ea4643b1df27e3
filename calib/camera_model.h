#pragma once
// Pinhole camera with Kalibr's two distortion models, templated so Ceres can autodiff it.
//   radtan (radial-tangential, k1 k2 p1 p2), as OpenCV's first four coefficients;
//   equidistant (k1..k4, Kannala-Brandt as Kalibr/OpenCV fisheye): theta_d = theta (1 + k1 t^2 +
//   k2 t^4 + k3 t^6 + k4 t^8) with theta = atan(r), r = |(x, y)| of the normalised point.
// params = [fu, fv, pu, pv, d0, d1, d2, d3].
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Core>

#include "data/euroc_sensor_yaml.h"

namespace adugs::calib {

using data::DistortionModel;

// Kalibr's names: "radtan", "equidistant". Also accepted: "radial-tangential" (EuRoC),
// "radtan4" (yac), "equi", "equi4", "fisheye". Returns false for anything else.
bool parseDistortionModel(const std::string& name, DistortionModel& out);
std::string kalibrName(DistortionModel model);

struct PinholeCamera {
  int width = 0, height = 0;
  DistortionModel model = DistortionModel::kRadialTangential;
  std::array<double, 8> params{};  // fu fv pu pv d0 d1 d2 d3

  double fu() const { return params[0]; }
  double fv() const { return params[1]; }
  double pu() const { return params[2]; }
  double pv() const { return params[3]; }

  // Projects a point in the camera frame; false when it is behind the camera.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const;
  // Inverse of project for a pixel: a unit-depth ray (z = 1). Iterative; false if it diverged.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const;

  data::CameraCalibration toEuroc() const;
};

// Distortion of a normalised point (x, y) -> (xd, yd).
template <typename T>
void distortPoint(DistortionModel model, const T* d, const T& x, const T& y, T& xd, T& yd) {
  using std::atan;
  using std::sqrt;
  if (model == DistortionModel::kRadialTangential) {
    const T r2 = x * x + y * y;
    const T radial = T(1) + d[0] * r2 + d[1] * r2 * r2;
    xd = x * radial + T(2) * d[2] * x * y + d[3] * (r2 + T(2) * x * x);
    yd = y * radial + d[2] * (r2 + T(2) * y * y) + T(2) * d[3] * x * y;
  } else {
    const T r2 = x * x + y * y;
    if (r2 < T(1e-16)) {  // theta_d / r -> 1 at the centre; sqrt' is infinite at 0
      xd = x;
      yd = y;
      return;
    }
    const T r = sqrt(r2);
    const T theta = atan(r);
    const T t2 = theta * theta;
    const T theta_d = theta * (T(1) + t2 * (d[0] + t2 * (d[1] + t2 * (d[2] + t2 * d[3]))));
    const T scale = theta_d / r;
    xd = x * scale;
    yd = y * scale;
  }
}

// Projects p_C (camera frame) with params [fu fv pu pv d0..d3]; false if z <= 0.
template <typename T>
bool projectPoint(DistortionModel model, const T* params, const T* p_C, T* uv) {
  if (!(p_C[2] > T(1e-9))) return false;
  const T x = p_C[0] / p_C[2];
  const T y = p_C[1] / p_C[2];
  T xd, yd;
  distortPoint(model, params + 4, x, y, xd, yd);
  uv[0] = params[0] * xd + params[2];
  uv[1] = params[1] * yd + params[3];
  return true;
}

}  // namespace adugs::calib

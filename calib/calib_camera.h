#pragma once
// The calibration's view of a camera: the pinhole parameter block Ceres optimises,
// params = [fu, fv, pu, pv, d0, d1, d2, d3], with Kalibr's radtan or equidistant distortion.
// The maths is data/camera_model.h's (data::projectPoint<T> in the cost functions,
// data::CameraModel for unprojection).
#include <Eigen/Core>
#include <array>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"

namespace adugs::calib {

using data::DistortionModel;

struct CalibCamera {
  int width = 0, height = 0;
  DistortionModel model = DistortionModel::kRadialTangential;
  std::array<double, 8> params{};  // fu fv pu pv d0 d1 d2 d3

  double fu() const { return params[0]; }
  double fv() const { return params[1]; }
  double pu() const { return params[2]; }
  double pv() const { return params[3]; }

  // Projects a point in the camera frame (data::projectPoint); false when it is behind the camera.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const;
  // Inverse of project for a pixel: a unit-depth ray (z = 1), by data::CameraModel::undistort;
  // false when the pixel has no such ray (a fisheye pixel 90 degrees or more off-axis). Needs a
  // valid camera (positive size and focal lengths), else throws std::invalid_argument.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const;

  // The same camera as the product's camera model, and as an EuRoC calibration.
  data::CameraModel cameraModel() const;
  data::CameraCalibration toEuroc() const;
};

}  // namespace adugs::calib

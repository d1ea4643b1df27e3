#pragma once
// The calibration's view of a camera: the parameter blocks Ceres optimises,
// params = [fu, fv, pu, pv, d0, d1, d2, d3] and projection_params = [q0, q1], for any projection
// of data/camera_model.h (pinhole; omni = unified/MEI: xi; ds: xi, alpha; eucm: alpha, beta) with
// Kalibr's radtan or equidistant distortion (omni: radtan or none; ds, eucm: none).
// The maths is data/camera_model.h's (data::projectPoint<T> in the cost functions,
// data::CameraModel for unprojection).
#include <Eigen/Core>
#include <array>
#include <string>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"

namespace adugs::calib {

using data::DistortionModel;
using data::ProjectionModel;

struct CalibCamera {
  int width = 0, height = 0;
  ProjectionModel projection = ProjectionModel::kPinhole;
  DistortionModel model = DistortionModel::kRadialTangential;
  std::array<double, 8> params{};             // fu fv pu pv d0 d1 d2 d3
  std::array<double, 2> projection_params{};  // omni: xi, 0; ds: xi alpha; eucm: alpha beta; pinhole: 0 0

  double fu() const { return params[0]; }
  double fv() const { return params[1]; }
  double pu() const { return params[2]; }
  double pv() const { return params[3]; }

  // Every parameter in one index range, for the covariance, the verdict and the report: 0..7 are
  // params, 8..9 projection_params (so the pinhole indices never moved).
  static constexpr int kParameters = 10;
  double parameter(int i) const { return i < 8 ? params[i] : projection_params[i - 8]; }
  double& parameter(int i) { return i < 8 ? params[i] : projection_params[i - 8]; }
  // Whether the model has parameter i (pinhole: no projection parameters; omni: xi only; ds and
  // eucm: no distortion coefficients; none: no coefficients).
  bool hasParameter(int i) const;
  // Kalibr's names: fu fv pu pv, k1 k2 p1 p2 (radtan) or k1..k4 (equidistant), xi, alpha, beta.
  std::string parameterName(int i) const;
  // The model as users name it (calib/lens_refit: radtan, equidistant, omni, omni-none, ds, eucm).
  std::string modelName() const;

  // Projects a point in the camera frame (data::projectPoint); false outside the projection's
  // valid region (pinhole: behind the camera).
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d& uv) const;
  // Inverse of project for a pixel: a unit-depth ray (z = 1); false when the pixel has no such
  // ray (a fisheye or wide-angle pixel 90 degrees or more off-axis, or outside the model's image).
  // Needs a valid camera (positive size and focal lengths, parameters in range), else throws
  // std::invalid_argument.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& ray) const;

  // The same camera as the product's camera model, and as an EuRoC calibration.
  data::CameraModel cameraModel() const;
  data::CameraCalibration toEuroc() const;
};

// The calibration camera of a calibration file's camera (projection and distortion kept).
CalibCamera fromCalibration(const data::CameraCalibration& camera);

}  // namespace adugs::calib

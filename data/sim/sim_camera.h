#pragma once
// The simulated camera as a description: size, intrinsics, a projection (pinhole by default; omni,
// ds, eucm for wide-angle lenses) and a radial-tangential (default, EuRoC cam0), equidistant
// (fisheye) or no distortion. All projection maths is data::CameraModel's (model()).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"

namespace adugs::data {

struct SimCamera {
  int width = 752;
  int height = 480;
  double fx = 458.654, fy = 457.296, cx = 367.215, cy = 248.375;
  // How rays reach the plane the distortion acts on, and its parameters (data/calibration.h).
  ProjectionModel projection = ProjectionModel::kPinhole;
  std::vector<double> projection_params;
  // radtan: k1, k2 radial, p1, p2 tangential (OpenCV order); equidistant: k1..k4; none: zeros.
  DistortionModel distortion_model = DistortionModel::kRadialTangential;
  std::array<double, 4> distortion{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};

  // The camera model (no distortion when radtan with all-zero coefficients). Throws
  // std::invalid_argument for an invalid description.
  CameraModel model() const;

  // Normalised undistorted (x, y) -> normalised distorted, and back (CameraModel::undistort).
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const { return model().distort(xy); }
  Eigen::Vector2d undistort(const Eigen::Vector2d& xy_distorted) const {
    return model().undistort(xy_distorted);
  }
  // Camera-frame point (z forward) -> pixel. False if the point is not in front of the camera
  // (z <= 1e-9); the pixel may still lie outside the image.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const {
    return model().project(p_C, uv);
  }
  // Pixel -> ray (x, y, 1) in the camera frame (not unit length: z = 1).
  Eigen::Vector3d unproject(const Eigen::Vector2d& uv) const { return model().unproject(uv); }

  // Whether straight lines stay straight in the image: false only for a pinhole camera without
  // distortion (none, or radtan with all-zero coefficients); equidistant and the wide-angle
  // projections always bend them.
  bool hasDistortion() const;
  bool inImage(const Eigen::Vector2d& uv) const {
    return uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() < width - 0.5 && uv.y() < height - 0.5;
  }
  // Same camera for an image scaled by s (intrinsics scaled; projection and distortion act on
  // normalised coordinates, unchanged).
  SimCamera scaled(double s) const;
};

// From a parsed EuRoC cam0/sensor.yaml (any projection and distortion); throws InputError
// (naming `source`) for anything the camera model refuses.
SimCamera simCameraFromCalibration(const CameraCalibration& calib, const std::string& source);
// The EuRoC description of a simulated camera.
CameraCalibration calibrationFromSimCamera(const SimCamera& camera, const Eigen::Isometry3d& T_B_C,
                                           double rate_hz);

}  // namespace adugs::data

#pragma once
// Pinhole camera with radial-tangential (plumb-bob, EuRoC/Kalibr "radtan") distortion, as the
// simulator needs it: project camera-frame points to pixels and turn pixels back into rays.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "data/euroc_sensor_yaml.h"

namespace adugs::data {

struct SimCamera {
  int width = 752;
  int height = 480;
  double fx = 458.654, fy = 457.296, cx = 367.215, cy = 248.375;
  // k1, k2 radial, p1, p2 tangential (OpenCV order).
  double k1 = -0.28340811, k2 = 0.07395907, p1 = 0.00019359, p2 = 1.76187114e-05;

  // Normalised undistorted (x, y) -> normalised distorted.
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const;
  // Inverse of distort by fixed-point iteration refined with Gauss-Newton; exact to ~1e-12 inside
  // the image.
  Eigen::Vector2d undistort(const Eigen::Vector2d& xy_distorted) const;

  // Camera-frame point (z forward) -> pixel. False if the point is not in front of the camera
  // (z <= 1e-9); the pixel may still lie outside the image.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const;
  // Pixel -> ray (x, y, 1) in the camera frame (not unit length: z = 1).
  Eigen::Vector3d unproject(const Eigen::Vector2d& uv) const;

  bool hasDistortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0; }
  bool inImage(const Eigen::Vector2d& uv) const {
    return uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() < width - 0.5 && uv.y() < height - 0.5;
  }
  // Same camera for an image scaled by s (intrinsics scaled, distortion unchanged).
  SimCamera scaled(double s) const;
};

// From a parsed EuRoC cam0/sensor.yaml; throws InputError (naming `source`) unless the model is
// pinhole radial-tangential.
SimCamera simCameraFromCalibration(const CameraCalibration& calib, const std::string& source);
// The EuRoC description of a simulated camera.
CameraCalibration calibrationFromSimCamera(const SimCamera& camera,
                                           const Eigen::Isometry3d& T_B_C, double rate_hz);

}  // namespace adugs::data

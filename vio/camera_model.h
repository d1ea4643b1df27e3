#pragma once
// Pinhole camera with radial-tangential (Kalibr "radtan", OpenCV plumb-bob k1 k2 p1 p2) or
// equidistant (Kalibr "equidistant", OpenCV fisheye k1..k4) distortion: what the front-end needs to
// turn tracked pixels into undistorted normalised coordinates (x/z, y/z) and back.
//
//   pixel uv  <->  distorted normalised xd  <->  undistorted normalised xn  <->  ray (xn, 1)
//
// Undistortion is iterative (Gauss-Newton on the 2-D radtan map, Newton on the 1-D equidistant
// angle map) and stops when the step is below 1e-12, so it is exact to ~1e-10 in normalised units
// over the image. Invalid parameters throw std::invalid_argument.
#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "data/euroc_sensor_yaml.h"

namespace adugs::vio {

class CameraModel {
 public:
  enum class Distortion { kNone, kRadialTangential, kEquidistant };

  CameraModel() = default;  // 0x0 camera, for default-constructed holders; do not use
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              Distortion distortion = Distortion::kNone, const std::array<double, 4>& coeffs = {});
  // From an EuRoC/Kalibr calibration (4 coefficients, radtan or equidistant).
  explicit CameraModel(const data::CameraCalibration& calibration);

  int width() const { return width_; }
  int height() const { return height_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  Distortion distortion() const { return distortion_; }
  const std::array<double, 4>& coeffs() const { return k_; }
  // The camera matrix K as OpenCV wants it (CV_64F 3x3) and the coefficients as a 1x4 Mat.
  cv::Mat cameraMatrix() const;
  cv::Mat distortionCoeffs() const;

  // Undistorted normalised -> distorted normalised (the lens model itself). With jacobian, also
  // d(xd)/d(xn).
  Eigen::Vector2d distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* jacobian = nullptr) const;
  // Inverse of distort. Equidistant pixels whose ray is 90 degrees or more off-axis have no
  // normalised coordinates; they come back as a (huge) point just short of 90 degrees.
  Eigen::Vector2d undistort(const Eigen::Vector2d& xd) const;

  // Undistorted normalised -> pixel.
  Eigen::Vector2d normalizedToPixel(const Eigen::Vector2d& xn) const;
  // Pixel -> undistorted normalised.
  Eigen::Vector2d pixelToNormalized(const Eigen::Vector2d& uv) const;
  // Batch version for the tracker (float pixels in, double normalised out).
  void pixelsToNormalized(const std::vector<cv::Point2f>& uv,
                          std::vector<Eigen::Vector2d>* xn) const;

  // Camera-frame point (z forward) -> pixel. False (uv untouched) when z <= 1e-9; the pixel may
  // still lie outside the image. Equidistant points at up to 90 degrees off-axis project fine.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const;
  // Pixel -> ray (x, y, 1).
  Eigen::Vector3d unproject(const Eigen::Vector2d& uv) const {
    const Eigen::Vector2d xn = pixelToNormalized(uv);
    return {xn.x(), xn.y(), 1.0};
  }

  // Pixel centre convention: pixel (0,0) covers [-0.5, 0.5]^2. border shrinks the box.
  bool inImage(double u, double v, double border = 0.0) const {
    return u >= border - 0.5 && v >= border - 0.5 && u <= width_ - 0.5 - border &&
           v <= height_ - 0.5 - border;
  }

 private:
  void validate() const;

  int width_ = 0, height_ = 0;
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  Distortion distortion_ = Distortion::kNone;
  std::array<double, 4> k_{};  // radtan: k1 k2 p1 p2; equidistant: k1 k2 k3 k4
};

}  // namespace adugs::vio

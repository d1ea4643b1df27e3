#pragma once
// The camera model of the whole product (simulator, front-end, estimator, calibration): pinhole
// with Kalibr's distortion models
//   none;
//   radtan (radial-tangential, k1 k2 p1 p2: OpenCV plumb-bob's first four coefficients);
//   equidistant (k1..k4, Kannala-Brandt as Kalibr and OpenCV fisheye):
//     theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//     theta = atan(r), r = |(x, y)| of the undistorted normalised point; xd = (theta_d / r) (x, y).
//
//   pixel uv  <->  distorted normalised xd  <->  undistorted normalised xn  <->  ray (xn, 1)
//
// One formula, two faces:
//   distortPoint<T>, projectPoint<T>: templated free functions, so Ceres can autodiff them
//     (calibration) with params = [fu fv pu pv d0 d1 d2 d3];
//   CameraModel: the class everything else holds. Its distort() evaluates distortPoint<double>
//     and adds an analytic Jacobian; undistort() is iterative (Gauss-Newton on the 2-D radtan map,
//     Newton on the 1-D equidistant angle map) and stops when the step is below 1e-12, so it is
//     exact to ~1e-10 in normalised units over the image.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "data/calibration.h"

namespace adugs::data {

// Kalibr's names: "radtan", "equidistant". Also accepted: "radial-tangential" (EuRoC),
// "radtan4" (yac), "equi", "equi4", "fisheye". Returns false for anything else.
bool parseDistortionModel(const std::string& name, DistortionModel& out);
// "radtan" / "equidistant" (Kalibr's spellings; toString() gives EuRoC's).
std::string kalibrName(DistortionModel model);

// Distortion of an undistorted normalised point (x, y) -> (xd, yd); d = 4 coefficients.
// The equidistant centre (r < 1e-12) maps to itself: theta_d / r -> 1 there, and the derivative of
// sqrt is infinite at 0.
template <typename T>
void distortPoint(DistortionModel model, const T* d, const T& x, const T& y, T& xd, T& yd) {
  using std::atan;
  using std::sqrt;
  const T r2 = x * x + y * y;
  if (model == DistortionModel::kRadialTangential) {
    const T radial = T(1) + d[0] * r2 + d[1] * r2 * r2;
    xd = x * radial + T(2) * d[2] * x * y + d[3] * (r2 + T(2) * x * x);
    yd = y * radial + d[2] * (r2 + T(2) * y * y) + T(2) * d[3] * x * y;
  } else {
    const T r = sqrt(r2);
    if (r < T(1e-12)) {
      xd = x;
      yd = y;
      return;
    }
    const T theta = atan(r);
    const T t2 = theta * theta;
    const T theta_d = theta * (T(1) + t2 * (d[0] + t2 * (d[1] + t2 * (d[2] + t2 * d[3]))));
    const T scale = theta_d / r;
    xd = x * scale;
    yd = y * scale;
  }
}

// Projects p_C (camera frame, z forward) with params [fu fv pu pv d0..d3]; false (uv untouched)
// when z <= 1e-9.
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

class CameraModel {
 public:
  enum class Distortion { kNone, kRadialTangential, kEquidistant };
  // The distortion of a calibration file's model.
  static Distortion fromModel(DistortionModel model);

  CameraModel() = default;  // 0x0 camera, for default-constructed holders; do not use
  // Throws std::invalid_argument for a non-positive size or focal length, or non-finite numbers.
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              Distortion distortion = Distortion::kNone, const std::array<double, 4>& coeffs = {});
  // From an EuRoC/Kalibr calibration (4 coefficients, radtan or equidistant).
  explicit CameraModel(const CameraCalibration& calibration);

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

  // Undistorted normalised -> distorted normalised (the lens model itself: distortPoint). With
  // jacobian, also d(xd)/d(xn).
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

}  // namespace adugs::data

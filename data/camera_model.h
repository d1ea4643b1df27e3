#pragma once
// The camera model of the whole product (simulator, front-end, estimator, calibration): a
// projection of the ray onto a plane, a lens distortion on that plane, then the camera matrix K.
//
//   ray p = (x, y, z)  --projection-->  m  --distortion-->  md  --K-->  pixel (fx md + cx, ...)
//
// Projections (data/calibration.h's ProjectionModel; params q = CameraCalibration::projection_params):
//   pinhole   m = (x, y) / z                                          valid for z > 1e-9
//   unified   m = (x, y) / (z + xi d),  d = |p|  (MEI; Kalibr "omni", camodocal/VINS "MEI")
//             valid for z > -w d,  w = xi (xi <= 1) or 1 / xi (xi > 1)   (Kalibr's region)
//   ds        m = (x, y) / (alpha d2 + (1 - alpha) k),  k = xi d + z,  d2 = |(x, y, k)|
//             (double sphere, Usenko et al. 2018, Basalt "ds"; valid for z > -w2 d with
//             w1 = alpha / (1 - alpha) (alpha <= 0.5) or (1 - alpha) / alpha, and
//             w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1))
//   eucm      m = (x, y) / (alpha rho + (1 - alpha) z),  rho = sqrt(beta (x^2 + y^2) + z^2)
//             (extended unified, Khomutenko et al. 2016, Basalt "eucm"; valid for z > -w rho,
//             w = alpha / (1 - alpha) (alpha <= 0.5) or (1 - alpha) / alpha)
// Distortions (Kalibr's), on the plane m, 4 coefficients:
//   none;
//   radtan (radial-tangential, k1 k2 p1 p2: OpenCV plumb-bob's first four coefficients; also the
//     MEI model's distortion, same formula in Kalibr omni-radtan and camodocal's CataCamera);
//   equidistant (k1..k4, Kannala-Brandt as Kalibr and OpenCV fisheye, Basalt kb4, pinhole only):
//     theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//     theta = atan(r), r = |m|; md = (theta_d / r) m.
// ds and eucm take no distortion (as in Basalt).
//
// One formula, two faces:
//   projectToPlane<T>, distortPoint<T>, projectPoint<T>: templated free functions, so Ceres can
//     autodiff them (calibration) with params = [fu fv pu pv d0 d1 d2 d3];
//   CameraModel: the class everything else holds, with analytic Jacobians and unprojection
//     (closed form for the projections; radtan undistortion is Gauss-Newton, equidistant Newton on
//     the angle, both stopping at a 1e-12 step, so exact to ~1e-10 in normalised units).
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "data/calibration.h"

namespace adugs::data {

// Kalibr's names: "radtan", "equidistant", "none". Also accepted: "radial-tangential" (EuRoC),
// "radtan4" (yac), "equi", "equi4", "fisheye". Returns false for anything else.
bool parseDistortionModel(const std::string& name, DistortionModel& out);
// "radtan" / "equidistant" / "none" (Kalibr's spellings; toString() gives EuRoC's).
std::string kalibrName(DistortionModel model);
// "pinhole", "omni" (also "mei", "unified"), "ds" (also "double-sphere"), "eucm" (also
// "extended-unified"). Returns false for anything else.
bool parseProjectionModel(const std::string& name, ProjectionModel& out);

// The denominator of the projection onto the model's plane, m = (x, y) / den (see above); q = the
// projection's parameters (none for pinhole). Returns whether p is in the valid region; den is
// the formula's value either way.
template <typename T>
bool planeDenominator(ProjectionModel model, const T* q, const T* p, T* den) {
  using std::sqrt;
  const T& x = p[0];
  const T& y = p[1];
  const T& z = p[2];
  switch (model) {
    case ProjectionModel::kPinhole:
      *den = z;
      return z > T(1e-9);
    case ProjectionModel::kUnified: {
      const T& xi = q[0];
      const T d = sqrt(x * x + y * y + z * z);
      const T w = xi <= T(1) ? xi : T(1) / xi;
      *den = z + xi * d;
      return d > T(0) && z > -w * d && *den > T(0);
    }
    case ProjectionModel::kDoubleSphere: {
      const T& xi = q[0];
      const T& alpha = q[1];
      const T r2 = x * x + y * y;
      const T d = sqrt(r2 + z * z);
      const T w1 = alpha > T(0.5) ? (T(1) - alpha) / alpha : alpha / (T(1) - alpha);
      const T w2 = (w1 + xi) / sqrt(T(2) * w1 * xi + xi * xi + T(1));
      const T k = xi * d + z;
      *den = alpha * sqrt(r2 + k * k) + (T(1) - alpha) * k;
      return d > T(0) && z > -w2 * d && *den > T(0);
    }
    case ProjectionModel::kExtendedUnified: {
      const T& alpha = q[0];
      const T& beta = q[1];
      const T rho = sqrt(beta * (x * x + y * y) + z * z);
      const T w = alpha > T(0.5) ? (T(1) - alpha) / alpha : alpha / (T(1) - alpha);
      *den = alpha * rho + (T(1) - alpha) * z;
      return rho > T(0) && z > -w * rho && *den > T(0);
    }
  }
  return false;
}

// Projection of a camera-frame point p onto the model's plane. False (m untouched) outside the
// model's valid region.
template <typename T>
bool projectToPlane(ProjectionModel model, const T* q, const T* p, T* m) {
  T den;
  if (!planeDenominator(model, q, p, &den)) return false;
  m[0] = p[0] / den;
  m[1] = p[1] / den;
  return true;
}

// Distortion of a point (x, y) on the projection plane -> (xd, yd); d = 4 coefficients (unused
// for none). The equidistant centre (r < 1e-12) maps to itself: theta_d / r -> 1 there, and the
// derivative of sqrt is infinite at 0.
template <typename T>
void distortPoint(DistortionModel model, const T* d, const T& x, const T& y, T& xd, T& yd) {
  using std::atan;
  using std::sqrt;
  if (model == DistortionModel::kNone) {
    xd = x;
    yd = y;
    return;
  }
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

// Projects p_C (camera frame, z forward) with any projection (q = its parameters) and
// params = [fu fv pu pv d0..d3]; false (uv untouched) outside the projection's valid region.
template <typename T>
bool projectPoint(ProjectionModel projection, const T* q, DistortionModel model, const T* params,
                  const T* p_C, T* uv) {
  T m[2];
  if (!projectToPlane(projection, q, p_C, m)) return false;
  T xd, yd;
  distortPoint(model, params + 4, m[0], m[1], xd, yd);
  uv[0] = params[0] * xd + params[2];
  uv[1] = params[1] * yd + params[3];
  return true;
}

// The pinhole case (the calibration's layout): false (uv untouched) when z <= 1e-9.
template <typename T>
bool projectPoint(DistortionModel model, const T* params, const T* p_C, T* uv) {
  return projectPoint<T>(ProjectionModel::kPinhole, nullptr, model, params, p_C, uv);
}

class CameraModel {
 public:
  enum class Distortion { kNone, kRadialTangential, kEquidistant };
  // The distortion of a calibration file's model.
  static Distortion fromModel(DistortionModel model);
  static DistortionModel toModel(Distortion distortion);

  CameraModel() = default;  // 0x0 camera, for default-constructed holders; do not use
  // A pinhole camera. Throws std::invalid_argument for a non-positive size or focal length, or
  // non-finite numbers.
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              Distortion distortion = Distortion::kNone, const std::array<double, 4>& coeffs = {});
  // Any projection with its projectionParameterCount() parameters. Throws std::invalid_argument
  // naming the parameter for a wrong count or a value out of range (omni: xi >= 0; ds: xi in
  // [-1, 1], alpha in [0, 1]; eucm: alpha in [0, 1], beta > 0), and for a distortion on ds or
  // eucm (radtan with zero coefficients counts as none) or equidistant on omni.
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              ProjectionModel projection, const std::vector<double>& projection_params,
              Distortion distortion = Distortion::kNone, const std::array<double, 4>& coeffs = {});
  // From a calibration (any projection; 4 coefficients, or none for distortion_model none).
  explicit CameraModel(const CameraCalibration& calibration);

  int width() const { return width_; }
  int height() const { return height_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  ProjectionModel projection() const { return projection_; }
  // projectionParameterCount(projection()) values.
  std::vector<double> projectionParams() const;
  bool isPinhole() const { return projection_ == ProjectionModel::kPinhole; }
  // Pixels per normalised unit on the optical axis, mean of both axes: the focal length pixel
  // thresholds and the estimator's pixel noise convert with. (fx + fy) / 2 for pinhole cameras;
  // the wide-angle projections scale it (omni and ds: / (1 + xi) there).
  double centreFocalPx() const;
  Distortion distortion() const { return distortion_; }
  const std::array<double, 4>& coeffs() const { return k_; }
  // The camera matrix K as OpenCV wants it (CV_64F 3x3) and the coefficients as a 1x4 Mat
  // (meaningful to OpenCV for pinhole cameras only).
  cv::Mat cameraMatrix() const;
  cv::Mat distortionCoeffs() const;

  // The whole lens between the pinhole normalised plane and K^-1 pixel: xn -> xd with
  // normalizedToPixel(xn) = K xd. For pinhole cameras this is the distortion itself
  // (distortPoint); for the others, project (xn, 1) then distort. With jacobian, also d(xd)/d(xn).
  Eigen::Vector2d distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* jacobian = nullptr) const;
  // Inverse of distort. A point with no normalised coordinates (its ray 90 degrees or more
  // off-axis, or outside the model's image region) comes back as a (huge) point just short of 90
  // degrees in its direction, as equidistant pixels always did; unproject(uv, &ray) tells them apart.
  Eigen::Vector2d undistort(const Eigen::Vector2d& xd) const;

  // Undistorted normalised -> pixel: project((xn, 1)). Outside the projection's valid region
  // (only some ds/eucm/omni rays close to 90 degrees) the value is the formula's, meaningless.
  Eigen::Vector2d normalizedToPixel(const Eigen::Vector2d& xn) const;
  // Pixel -> undistorted normalised: the ray divided by its z, for rays in front of the camera
  // (else clamped as undistort says).
  Eigen::Vector2d pixelToNormalized(const Eigen::Vector2d& uv) const;
  // Batch version for the tracker (float pixels in, double normalised out).
  void pixelsToNormalized(const std::vector<cv::Point2f>& uv,
                          std::vector<Eigen::Vector2d>* xn) const;

  // Camera-frame point (z forward) -> pixel, with d(uv)/d(p_C) when jacobian is given. False (uv
  // untouched) outside the projection's valid region (pinhole: z <= 1e-9); the pixel may still
  // lie outside the image. Equidistant points at up to 90 degrees off-axis project fine.
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv,
               Eigen::Matrix<double, 2, 3>* jacobian = nullptr) const;
  // Pixel -> unit ray. False (ray untouched) for a pixel no ray projects to: outside the model's
  // image region (omni xi > 1, ds/eucm alpha > 0.5), where the distortion cannot be inverted, or
  // (pinhole) 90 degrees or more off-axis.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* ray) const;
  // Pixel -> ray (x, y, 1) = pixelToNormalized(uv), 1.
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
  // The distortion on the projection plane, with d(md)/d(m), and its inverse (false when it does
  // not converge to md).
  Eigen::Vector2d distortPlane(const Eigen::Vector2d& m, Eigen::Matrix2d* jacobian) const;
  bool undistortPlane(const Eigen::Vector2d& md, Eigen::Vector2d* m) const;
  // d(m)/d(p) of projectToPlane (p in the valid region).
  Eigen::Matrix<double, 2, 3> planeJacobian(const Eigen::Vector3d& p) const;
  // Plane point -> unit ray (the projection's closed-form inverse); false outside its image.
  bool liftFromPlane(const Eigen::Vector2d& m, Eigen::Vector3d* ray) const;

  int width_ = 0, height_ = 0;
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  ProjectionModel projection_ = ProjectionModel::kPinhole;
  std::array<double, 2> q_{};  // omni: xi; ds: xi alpha; eucm: alpha beta
  Distortion distortion_ = Distortion::kNone;
  std::array<double, 4> k_{};  // radtan: k1 k2 p1 p2; equidistant: k1 k2 k3 k4
};

}  // namespace adugs::data

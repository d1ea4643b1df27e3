#include "data/camera_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

namespace adugs::data {
namespace {

constexpr int kMaxIterations = 50;
constexpr double kStepTolerance = 1e-12;  // normalised units; the result is good to ~1e-10

std::array<double, 4> coeffsOf(const CameraCalibration& c) {
  if (c.distortion.size() != 4)
    throw std::invalid_argument("CameraModel: expected 4 distortion coefficients, got " +
                                std::to_string(c.distortion.size()));
  return {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3]};
}

}  // namespace

bool parseDistortionModel(const std::string& name, DistortionModel& out) {
  if (name == "radtan" || name == "radial-tangential" || name == "radtan4") {
    out = DistortionModel::kRadialTangential;
    return true;
  }
  if (name == "equidistant" || name == "equi" || name == "equi4" || name == "fisheye") {
    out = DistortionModel::kEquidistant;
    return true;
  }
  return false;
}

std::string kalibrName(DistortionModel model) {
  return model == DistortionModel::kRadialTangential ? "radtan" : "equidistant";
}

CameraModel::Distortion CameraModel::fromModel(DistortionModel model) {
  return model == DistortionModel::kEquidistant ? Distortion::kEquidistant
                                                : Distortion::kRadialTangential;
}

CameraModel::CameraModel(int width, int height, double fx, double fy, double cx, double cy,
                         Distortion distortion, const std::array<double, 4>& coeffs)
    : width_(width),
      height_(height),
      fx_(fx),
      fy_(fy),
      cx_(cx),
      cy_(cy),
      distortion_(distortion),
      k_(coeffs) {
  validate();
}

CameraModel::CameraModel(const CameraCalibration& c)
    : CameraModel(c.width, c.height, c.fx, c.fy, c.cx, c.cy, fromModel(c.distortion_model),
                  coeffsOf(c)) {}

void CameraModel::validate() const {
  bool ok = width_ > 0 && height_ > 0 && std::isfinite(fx_) && std::isfinite(fy_) && fx_ > 0 &&
            fy_ > 0 && std::isfinite(cx_) && std::isfinite(cy_);
  for (double k : k_) ok = ok && std::isfinite(k);
  if (!ok)
    throw std::invalid_argument("CameraModel: invalid size, focal length, centre or coefficients");
}

cv::Mat CameraModel::cameraMatrix() const {
  return (cv::Mat_<double>(3, 3) << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1);
}

cv::Mat CameraModel::distortionCoeffs() const {
  if (distortion_ == Distortion::kNone) return cv::Mat::zeros(1, 4, CV_64F);
  return (cv::Mat_<double>(1, 4) << k_[0], k_[1], k_[2], k_[3]);
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* jacobian) const {
  if (distortion_ == Distortion::kNone) {
    if (jacobian) jacobian->setIdentity();
    return xn;
  }
  const bool radtan = distortion_ == Distortion::kRadialTangential;
  Eigen::Vector2d xd;
  distortPoint(radtan ? DistortionModel::kRadialTangential : DistortionModel::kEquidistant,
               k_.data(), xn.x(), xn.y(), xd.x(), xd.y());
  if (!jacobian) return xd;

  // The analytic Jacobian of the same formula.
  const double x = xn.x(), y = xn.y();
  const double r2 = x * x + y * y;
  if (radtan) {
    const double k1 = k_[0], k2 = k_[1], p1 = k_[2], p2 = k_[3];
    const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
    const double dradial = 2.0 * (k1 + 2.0 * k2 * r2);  // d radial / d(x or y) = dradial * x
    (*jacobian)(0, 0) = radial + dradial * x * x + 2.0 * p1 * y + 6.0 * p2 * x;
    (*jacobian)(0, 1) = dradial * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jacobian)(1, 0) = (*jacobian)(0, 1);
    (*jacobian)(1, 1) = radial + dradial * y * y + 6.0 * p1 * y + 2.0 * p2 * x;
    return xd;
  }
  const double r = std::sqrt(r2);
  if (r < 1e-12) {  // distortPoint's centre: the identity
    jacobian->setIdentity();
    return xd;
  }
  const double th = std::atan(r), th2 = th * th;
  const double thd = th * (1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3]))));
  const double s = thd / r;
  const double dthd_dth =
      1.0 + th2 * (3 * k_[0] + th2 * (5 * k_[1] + th2 * (7 * k_[2] + th2 * 9 * k_[3])));
  const double dthd_dr = dthd_dth / (1.0 + r * r);
  const double ds_dr = (dthd_dr * r - thd) / (r * r);
  *jacobian = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * xn * xn.transpose();
  return xd;
}

Eigen::Vector2d CameraModel::undistort(const Eigen::Vector2d& xd) const {
  switch (distortion_) {
    case Distortion::kNone:
      return xd;
    case Distortion::kEquidistant: {
      // The model only scales the radius: solve theta_d(theta) = |xd| for theta (1-D Newton).
      const double rd = xd.norm();
      if (rd < 1e-12) return xd;
      double th = std::min(rd, 1.5);
      for (int i = 0; i < kMaxIterations; ++i) {
        const double th2 = th * th;
        const double f =
            th * (1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3])))) - rd;
        const double df =
            1.0 + th2 * (3 * k_[0] + th2 * (5 * k_[1] + th2 * (7 * k_[2] + th2 * 9 * k_[3])));
        const double step = f / df;
        th -= step;
        if (std::abs(step) < kStepTolerance) break;
      }
      // Rays at or beyond 90 degrees have no normalised coordinates: stop just short of it.
      th = std::min(th, 0.5 * M_PI - 1e-9);
      return xd * (std::tan(th) / rd);
    }
    case Distortion::kRadialTangential: {
      // Gauss-Newton on distort(x) = xd from x = xd; converges in a handful of iterations over
      // the EuRoC image (k1 = -0.28), where plain fixed-point iteration needs dozens.
      Eigen::Vector2d x = xd;
      Eigen::Matrix2d J;
      for (int i = 0; i < kMaxIterations; ++i) {
        const Eigen::Vector2d residual = distort(x, &J) - xd;
        const Eigen::Vector2d step = J.partialPivLu().solve(residual);
        if (!step.allFinite()) break;
        x -= step;
        if (step.norm() < kStepTolerance) break;
      }
      return x;
    }
  }
  return xd;
}

Eigen::Vector2d CameraModel::normalizedToPixel(const Eigen::Vector2d& xn) const {
  const Eigen::Vector2d xd = distort(xn);
  return {fx_ * xd.x() + cx_, fy_ * xd.y() + cy_};
}

Eigen::Vector2d CameraModel::pixelToNormalized(const Eigen::Vector2d& uv) const {
  return undistort({(uv.x() - cx_) / fx_, (uv.y() - cy_) / fy_});
}

void CameraModel::pixelsToNormalized(const std::vector<cv::Point2f>& uv,
                                     std::vector<Eigen::Vector2d>* xn) const {
  xn->resize(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) (*xn)[i] = pixelToNormalized({uv[i].x, uv[i].y});
}

bool CameraModel::project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const {
  if (!(p_C.z() > 1e-9)) return false;
  *uv = normalizedToPixel(p_C.head<2>() / p_C.z());
  return true;
}

}  // namespace adugs::data

#include "data/camera_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace adugs::data {
namespace {

constexpr int kMaxIterations = 50;
constexpr double kStepTolerance = 1e-12;  // normalised units; the result is good to ~1e-10
// An undistorted point whose distortion misses its target by more than this did not converge.
constexpr double kUndistortTolerance = 1e-8;
// Rays at or beyond 90 degrees have no normalised coordinates: they stop just short of it.
constexpr double kMaxNormalizedAngle = 0.5 * M_PI - 1e-9;

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::array<double, 4> coeffsOf(const CameraCalibration& c) {
  // 'none' keeps four zero coefficients; an empty list is read as the same.
  if (c.distortion_model == DistortionModel::kNone && c.distortion.empty()) return {};
  if (c.distortion.size() != 4)
    throw std::invalid_argument("CameraModel: expected 4 distortion coefficients, got " +
                                std::to_string(c.distortion.size()));
  return {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3]};
}

// The point at angle theta off-axis in the direction of dir (normalised coordinates).
Eigen::Vector2d atAngle(const Eigen::Vector2d& dir, double theta) {
  const double n = dir.norm();
  if (!(n > 0)) return Eigen::Vector2d::Zero();
  return dir * (std::tan(theta) / n);
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
  if (name == "none") {
    out = DistortionModel::kNone;
    return true;
  }
  return false;
}

std::string kalibrName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: return "none";
    case DistortionModel::kRadialTangential: break;
  }
  return "radtan";
}

bool parseProjectionModel(const std::string& name, ProjectionModel& out) {
  if (name == "pinhole") {
    out = ProjectionModel::kPinhole;
  } else if (name == "omni" || name == "mei" || name == "MEI" || name == "unified") {
    out = ProjectionModel::kUnified;
  } else if (name == "ds" || name == "double-sphere") {
    out = ProjectionModel::kDoubleSphere;
  } else if (name == "eucm" || name == "extended-unified") {
    out = ProjectionModel::kExtendedUnified;
  } else {
    return false;
  }
  return true;
}

CameraModel::Distortion CameraModel::fromModel(DistortionModel model) {
  switch (model) {
    case DistortionModel::kEquidistant: return Distortion::kEquidistant;
    case DistortionModel::kNone: return Distortion::kNone;
    case DistortionModel::kRadialTangential: break;
  }
  return Distortion::kRadialTangential;
}

DistortionModel CameraModel::toModel(Distortion distortion) {
  switch (distortion) {
    case Distortion::kEquidistant: return DistortionModel::kEquidistant;
    case Distortion::kNone: return DistortionModel::kNone;
    case Distortion::kRadialTangential: break;
  }
  return DistortionModel::kRadialTangential;
}

CameraModel::CameraModel(int width, int height, double fx, double fy, double cx, double cy,
                         Distortion distortion, const std::array<double, 4>& coeffs)
    : CameraModel(width, height, fx, fy, cx, cy, ProjectionModel::kPinhole, {}, distortion,
                  coeffs) {}

CameraModel::CameraModel(int width, int height, double fx, double fy, double cx, double cy,
                         ProjectionModel projection, const std::vector<double>& projection_params,
                         Distortion distortion, const std::array<double, 4>& coeffs)
    : width_(width),
      height_(height),
      fx_(fx),
      fy_(fy),
      cx_(cx),
      cy_(cy),
      projection_(projection),
      distortion_(distortion),
      k_(coeffs) {
  const int n = projectionParameterCount(projection);
  if (static_cast<int>(projection_params.size()) != n)
    throw std::invalid_argument("CameraModel: projection " + toString(projection) + " needs " +
                                std::to_string(n) + " projection_params, got " +
                                std::to_string(projection_params.size()));
  for (int i = 0; i < n; ++i) q_[static_cast<size_t>(i)] = projection_params[static_cast<size_t>(i)];
  // ds and eucm have no distortion; a radtan model with zero coefficients (the calibration's
  // default) is none.
  const bool zero = std::all_of(k_.begin(), k_.end(), [](double k) { return k == 0.0; });
  if (distortion_ == Distortion::kRadialTangential && zero && !isPinhole()) distortion_ = Distortion::kNone;
  validate();
}

CameraModel::CameraModel(const CameraCalibration& c)
    : CameraModel(c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.projection, c.projection_params,
                  fromModel(c.distortion_model), coeffsOf(c)) {}

void CameraModel::validate() const {
  bool ok = width_ > 0 && height_ > 0 && std::isfinite(fx_) && std::isfinite(fy_) && fx_ > 0 &&
            fy_ > 0 && std::isfinite(cx_) && std::isfinite(cy_);
  for (double k : k_) ok = ok && std::isfinite(k);
  if (!ok)
    throw std::invalid_argument("CameraModel: invalid size, focal length, centre or coefficients");
  const std::string name = "CameraModel: " + toString(projection_) + " ";
  auto require = [&](bool good, const std::string& param, double value, const std::string& range) {
    if (!good)
      throw std::invalid_argument(name + param + " must be " + range + " (got " + str(value) + ")");
  };
  switch (projection_) {
    case ProjectionModel::kPinhole:
      break;
    case ProjectionModel::kUnified:
      require(q_[0] >= 0 && std::isfinite(q_[0]), "xi", q_[0], ">= 0");
      if (distortion_ == Distortion::kEquidistant)
        throw std::invalid_argument(name + "takes radtan or no distortion (distortion_model " +
                                    "equidistant is for pinhole cameras)");
      break;
    case ProjectionModel::kDoubleSphere:
      require(q_[0] >= -1 && q_[0] <= 1, "xi", q_[0], "in [-1, 1]");
      require(q_[1] >= 0 && q_[1] <= 1, "alpha", q_[1], "in [0, 1]");
      break;
    case ProjectionModel::kExtendedUnified:
      require(q_[0] >= 0 && q_[0] <= 1, "alpha", q_[0], "in [0, 1]");
      require(q_[1] > 0 && std::isfinite(q_[1]), "beta", q_[1], "> 0");
      break;
  }
  if ((projection_ == ProjectionModel::kDoubleSphere ||
       projection_ == ProjectionModel::kExtendedUnified) &&
      distortion_ != Distortion::kNone)
    throw std::invalid_argument(name + "takes no distortion (distortion_model must be none, got " +
                                kalibrName(toModel(distortion_)) + ")");
}

double CameraModel::centreFocalPx() const {
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> J;
  project(Eigen::Vector3d::UnitZ(), &uv, &J);  // d(uv)/d(xn) at xn = 0 is J's left 2x2
  return 0.5 * (J(0, 0) + J(1, 1));
}

std::vector<double> CameraModel::projectionParams() const {
  return std::vector<double>(q_.begin(), q_.begin() + projectionParameterCount(projection_));
}

cv::Mat CameraModel::cameraMatrix() const {
  return (cv::Mat_<double>(3, 3) << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1);
}

cv::Mat CameraModel::distortionCoeffs() const {
  if (distortion_ == Distortion::kNone) return cv::Mat::zeros(1, 4, CV_64F);
  return (cv::Mat_<double>(1, 4) << k_[0], k_[1], k_[2], k_[3]);
}

Eigen::Vector2d CameraModel::distortPlane(const Eigen::Vector2d& m, Eigen::Matrix2d* jacobian) const {
  Eigen::Vector2d md;
  distortPoint(toModel(distortion_), k_.data(), m.x(), m.y(), md.x(), md.y());
  if (!jacobian) return md;

  // The analytic Jacobian of the same formula.
  const double x = m.x(), y = m.y();
  const double r2 = x * x + y * y;
  switch (distortion_) {
    case Distortion::kNone:
      jacobian->setIdentity();
      break;
    case Distortion::kRadialTangential: {
      const double k1 = k_[0], k2 = k_[1], p1 = k_[2], p2 = k_[3];
      const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
      const double dradial = 2.0 * (k1 + 2.0 * k2 * r2);  // d radial / d(x or y) = dradial * x
      (*jacobian)(0, 0) = radial + dradial * x * x + 2.0 * p1 * y + 6.0 * p2 * x;
      (*jacobian)(0, 1) = dradial * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
      (*jacobian)(1, 0) = (*jacobian)(0, 1);
      (*jacobian)(1, 1) = radial + dradial * y * y + 6.0 * p1 * y + 2.0 * p2 * x;
      break;
    }
    case Distortion::kEquidistant: {
      const double r = std::sqrt(r2);
      if (r < 1e-12) {  // distortPoint's centre: the identity
        jacobian->setIdentity();
        break;
      }
      const double th = std::atan(r), th2 = th * th;
      const double thd = th * (1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3]))));
      const double s = thd / r;
      const double dthd_dth =
          1.0 + th2 * (3 * k_[0] + th2 * (5 * k_[1] + th2 * (7 * k_[2] + th2 * 9 * k_[3])));
      const double dthd_dr = dthd_dth / (1.0 + r * r);
      const double ds_dr = (dthd_dr * r - thd) / (r * r);
      *jacobian = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * m * m.transpose();
      break;
    }
  }
  return md;
}

bool CameraModel::undistortPlane(const Eigen::Vector2d& md, Eigen::Vector2d* m) const {
  switch (distortion_) {
    case Distortion::kNone:
      *m = md;
      return true;
    case Distortion::kEquidistant: {
      // The model only scales the radius: solve theta_d(theta) = |md| for theta (1-D Newton).
      const double rd = md.norm();
      if (rd < 1e-12) {
        *m = md;
        return true;
      }
      double th = std::min(rd, 1.5);
      double f = 0;
      for (int i = 0; i < kMaxIterations; ++i) {
        const double th2 = th * th;
        f = th * (1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3])))) - rd;
        const double df =
            1.0 + th2 * (3 * k_[0] + th2 * (5 * k_[1] + th2 * (7 * k_[2] + th2 * 9 * k_[3])));
        const double step = f / df;
        th -= step;
        if (std::abs(step) < kStepTolerance) break;
      }
      const bool ok = std::abs(f) < kUndistortTolerance && th < kMaxNormalizedAngle;
      *m = md * (std::tan(std::min(th, kMaxNormalizedAngle)) / rd);
      return ok;
    }
    case Distortion::kRadialTangential: {
      // Gauss-Newton on distort(x) = md from x = md; converges in a handful of iterations over
      // the EuRoC image (k1 = -0.28), where plain fixed-point iteration needs dozens.
      Eigen::Vector2d x = md;
      Eigen::Matrix2d J;
      for (int i = 0; i < kMaxIterations; ++i) {
        const Eigen::Vector2d residual = distortPlane(x, &J) - md;
        const Eigen::Vector2d step = J.partialPivLu().solve(residual);
        if (!step.allFinite()) break;
        x -= step;
        if (step.norm() < kStepTolerance) break;
      }
      *m = x;
      return x.allFinite() &&
             (distortPlane(x, nullptr) - md).norm() < kUndistortTolerance * std::max(1.0, md.norm());
    }
  }
  *m = md;
  return true;
}

Eigen::Matrix<double, 2, 3> CameraModel::planeJacobian(const Eigen::Vector3d& p) const {
  // m = (x, y) / den  =>  dm/dp = ([I 0] - m g^T) / den with g = d(den)/dp.
  double den = 0;
  planeDenominator(projection_, q_.data(), p.data(), &den);
  Eigen::Vector3d g = Eigen::Vector3d::UnitZ();
  const double x = p.x(), y = p.y(), z = p.z();
  switch (projection_) {
    case ProjectionModel::kPinhole:
      break;
    case ProjectionModel::kUnified:  // den = z + xi |p|
      g += q_[0] * p / p.norm();
      break;
    case ProjectionModel::kDoubleSphere: {  // den = alpha d2 + (1 - alpha) k
      const double xi = q_[0], alpha = q_[1];
      const double d = p.norm();
      const double k = xi * d + z;
      const double d2 = std::sqrt(x * x + y * y + k * k);
      const Eigen::Vector3d dk = xi * p / d + Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d dd2 = (Eigen::Vector3d(x, y, 0) + k * dk) / d2;
      g = alpha * dd2 + (1 - alpha) * dk;
      break;
    }
    case ProjectionModel::kExtendedUnified: {  // den = alpha rho + (1 - alpha) z
      const double alpha = q_[0], beta = q_[1];
      const double rho = std::sqrt(beta * (x * x + y * y) + z * z);
      g = alpha * Eigen::Vector3d(beta * x, beta * y, z) / rho + (1 - alpha) * Eigen::Vector3d::UnitZ();
      break;
    }
  }
  const Eigen::Vector2d m(x / den, y / den);
  Eigen::Matrix<double, 2, 3> J = -m * g.transpose();
  J(0, 0) += 1;
  J(1, 1) += 1;
  return J / den;
}

bool CameraModel::liftFromPlane(const Eigen::Vector2d& m, Eigen::Vector3d* ray) const {
  const double r2 = m.squaredNorm();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  switch (projection_) {
    case ProjectionModel::kPinhole:
      r = Eigen::Vector3d(m.x(), m.y(), 1.0).normalized();
      break;
    case ProjectionModel::kUnified: {
      // The unit-sphere point (lambda m, lambda - xi) with |.| = 1 (the larger root).
      const double xi = q_[0];
      const double disc = 1.0 + (1.0 - xi * xi) * r2;  // < 0 outside the image of xi > 1
      if (!(disc >= 0)) return false;
      const double lambda = (xi + std::sqrt(disc)) / (1.0 + r2);
      r = Eigen::Vector3d(lambda * m.x(), lambda * m.y(), lambda - xi);
      break;
    }
    case ProjectionModel::kDoubleSphere: {
      // Undo the second sphere (alpha) to get the point on the plane at mz, then the first (xi).
      const double xi = q_[0], alpha = q_[1];
      const double s = 1.0 - (2.0 * alpha - 1.0) * r2;  // <= 0 outside the image of alpha > 0.5
      if (!(s > 0)) return false;
      const double mz = (1.0 - alpha * alpha * r2) / (alpha * std::sqrt(s) + 1.0 - alpha);
      const double disc = mz * mz + (1.0 - xi * xi) * r2;
      if (!(disc >= 0)) return false;
      const double k = (mz * xi + std::sqrt(disc)) / (mz * mz + r2);
      r = Eigen::Vector3d(k * m.x(), k * m.y(), k * mz - xi);
      break;
    }
    case ProjectionModel::kExtendedUnified: {
      const double alpha = q_[0], beta = q_[1];
      const double s = 1.0 - (2.0 * alpha - 1.0) * beta * r2;  // likewise for alpha > 0.5
      if (!(s > 0)) return false;
      const double mz = (1.0 - beta * alpha * alpha * r2) / (alpha * std::sqrt(s) + 1.0 - alpha);
      r = Eigen::Vector3d(m.x(), m.y(), mz);
      break;
    }
  }
  if (!r.allFinite() || !(r.norm() > 0)) return false;
  r.normalize();
  // The region's edge: a ray that would not project back is no ray of this camera.
  double den;
  if (!planeDenominator(projection_, q_.data(), r.data(), &den)) return false;
  *ray = r;
  return true;
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* jacobian) const {
  if (isPinhole()) return distortPlane(xn, jacobian);
  const Eigen::Vector3d p(xn.x(), xn.y(), 1.0);
  double den;
  planeDenominator(projection_, q_.data(), p.data(), &den);
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d md = distortPlane(xn / den, jacobian ? &Jd : nullptr);
  if (jacobian) *jacobian = Jd * planeJacobian(p).leftCols<2>();
  return md;
}

Eigen::Vector2d CameraModel::undistort(const Eigen::Vector2d& xd) const {
  Eigen::Vector2d m;
  const bool undistorted = undistortPlane(xd, &m);
  if (isPinhole()) return m;  // equidistant: already stopped short of 90 degrees
  Eigen::Vector3d ray;
  if (!undistorted || !liftFromPlane(m, &ray))
    return atAngle(xd, kMaxNormalizedAngle);  // no ray: its direction at 90 degrees
  const double theta = std::atan2(ray.head<2>().norm(), ray.z());
  if (theta >= kMaxNormalizedAngle) return atAngle(ray.head<2>(), kMaxNormalizedAngle);
  return ray.head<2>() / ray.z();
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

bool CameraModel::project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv,
                          Eigen::Matrix<double, 2, 3>* jacobian) const {
  Eigen::Vector2d m;
  if (!projectToPlane(projection_, q_.data(), p_C.data(), m.data())) return false;
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d md = distortPlane(m, jacobian ? &Jd : nullptr);
  *uv = Eigen::Vector2d(fx_ * md.x() + cx_, fy_ * md.y() + cy_);
  if (jacobian) *jacobian = Eigen::Vector2d(fx_, fy_).asDiagonal() * Jd * planeJacobian(p_C);
  return true;
}

bool CameraModel::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* ray) const {
  Eigen::Vector2d m;
  if (!undistortPlane({(uv.x() - cx_) / fx_, (uv.y() - cy_) / fy_}, &m)) return false;
  return liftFromPlane(m, ray);
}

}  // namespace adugs::data

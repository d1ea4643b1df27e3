#include "calib/camera_imu/camera_imu_init.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace adugs::calib {

std::vector<BoardPose> estimateBoardPoses(const std::vector<TargetObservation>& views,
                                          const CalibCamera& camera, int64_t origin_ns,
                                          int min_corners, double max_rms_px) {
  std::vector<BoardPose> poses;
  for (size_t v = 0; v < views.size(); ++v) {
    const auto& corners = views[v].corners;
    if (static_cast<int>(corners.size()) < min_corners) continue;
    // Undistort to normalised coordinates, then PnP with an identity camera matrix.
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const auto& c : corners) {
      Eigen::Vector3d ray;
      if (!camera.unproject(c.pixel, ray)) continue;
      object.emplace_back(c.point.x(), c.point.y(), c.point.z());
      image.emplace_back(ray.x(), ray.y());
    }
    if (static_cast<int>(object.size()) < min_corners) continue;
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(object, image, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec, false,
                      cv::SOLVEPNP_IPPE))
      continue;
    cv::solvePnPRefineLM(object, image, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec);
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d R_C_T;
    Eigen::Vector3d t_C_T;
    cv::cv2eigen(R, R_C_T);
    cv::cv2eigen(tvec, t_C_T);
    double sq = 0;
    int n = 0;
    for (const auto& c : corners) {
      Eigen::Vector2d uv;
      if (!camera.project(R_C_T * c.point + t_C_T, uv)) continue;
      sq += (uv - c.pixel).squaredNorm();
      ++n;
    }
    if (n < min_corners) continue;
    BoardPose p;
    p.rms_px = std::sqrt(sq / n);
    if (!(p.rms_px <= max_rms_px)) continue;
    p.t = static_cast<double>(views[v].t_ns - origin_ns) * 1e-9;
    p.view = v;
    p.q_T_C = Eigen::Quaterniond(R_C_T.transpose());
    p.p_T_C = -(R_C_T.transpose() * t_C_T);
    poses.push_back(p);
  }
  return poses;
}

std::vector<RateSample> cameraAngularRates(const std::vector<BoardPose>& poses, double max_gap_s) {
  std::vector<RateSample> rates;
  for (size_t k = 1; k < poses.size(); ++k) {
    const double dt = poses[k].t - poses[k - 1].t;
    if (!(dt > 0 && dt <= max_gap_s)) continue;
    const Eigen::AngleAxisd aa(poses[k - 1].q_T_C.conjugate() * poses[k].q_T_C);
    rates.push_back({0.5 * (poses[k].t + poses[k - 1].t), aa.axis() * aa.angle() / dt});
  }
  return rates;
}

bool meanRate(const std::vector<RateSample>& imu, double t0, double t1, Eigen::Vector3d& mean) {
  auto first = std::lower_bound(imu.begin(), imu.end(), t0,
                                [](const RateSample& s, double t) { return s.t < t; });
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (auto it = first; it != imu.end() && it->t <= t1; ++it, ++n) sum += it->omega;
  if (n == 0) return false;
  mean = sum / n;
  return true;
}

double timeOffsetByCorrelation(const std::vector<RateSample>& camera_rates,
                               const std::vector<RateSample>& imu, double frame_interval_s,
                               double max_shift_s) {
  if (imu.size() < 2 || camera_rates.empty()) return 0;
  const double step = (imu.back().t - imu.front().t) / (imu.size() - 1);
  const int steps = static_cast<int>(std::ceil(max_shift_s / step));
  double best = -2, best_shift = 0;
  const double half = 0.5 * frame_interval_s;
  for (int s = -steps; s <= steps; ++s) {
    const double shift = s * step;
    // Pearson correlation of the two norm series over the pairs both cover.
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    int n = 0;
    for (const auto& c : camera_rates) {
      Eigen::Vector3d g;
      if (!meanRate(imu, c.t + shift - half, c.t + shift + half, g)) continue;
      const double a = c.omega.norm(), b = g.norm();
      sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b, ++n;
    }
    if (n < 10) continue;
    const double cov = sab / n - sa / n * sb / n;
    const double va = saa / n - sa / n * sa / n, vb = sbb / n - sb / n * sb / n;
    if (!(va > 0 && vb > 0)) continue;
    const double r = cov / std::sqrt(va * vb);
    if (r > best) best = r, best_shift = shift;
  }
  return best_shift;
}

Eigen::Matrix3d alignVectors(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < a.size(); ++i) H += b[i] * a[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

Eigen::Matrix3d rotationFromAngularRates(const std::vector<RateSample>& camera_rates,
                                         const std::vector<RateSample>& imu,
                                         double frame_interval_s, double shift_s, double* rms_out) {
  std::vector<Eigen::Vector3d> cam, gyro;
  const double half = 0.5 * frame_interval_s;
  for (const auto& c : camera_rates) {
    Eigen::Vector3d g;
    if (!meanRate(imu, c.t + shift_s - half, c.t + shift_s + half, g)) continue;
    cam.push_back(c.omega);
    gyro.push_back(g);
  }
  const Eigen::Matrix3d R = alignVectors(cam, gyro);
  if (rms_out) {
    double sq = 0;
    for (size_t i = 0; i < cam.size(); ++i) sq += (cam[i] - R * gyro[i]).squaredNorm();
    *rms_out = cam.empty() ? 0 : std::sqrt(sq / cam.size());
  }
  return R;
}

Eigen::Vector3d rotationExcitation(const std::vector<RateSample>& imu) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const auto& s : imu) S += s.omega * s.omega.transpose();
  if (!imu.empty()) S /= static_cast<double>(imu.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
  const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0).cwiseSqrt();  // ascending
  return Eigen::Vector3d(ev(2), ev(1), ev(0));
}

}  // namespace adugs::calib

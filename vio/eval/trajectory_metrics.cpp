#include "vio/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace adugs::vio {
namespace {

constexpr double kRadToDeg = 180.0 / EIGEN_PI;

void checkMatched(const data::Trajectory& est, const data::Trajectory& gt) {
  if (est.size() != gt.size())
    throw std::invalid_argument("trajectory metrics: " + std::to_string(est.size()) +
                                " estimated vs " + std::to_string(gt.size()) +
                                " ground-truth poses");
  if (est.empty()) throw std::invalid_argument("trajectory metrics: no pose pairs");
}

double angleDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * kRadToDeg; }

Eigen::Isometry3d isometry(const data::StampedPose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = pose.q_W_B.normalized().toRotationMatrix();
  T.translation() = pose.p_W_B;
  return T;
}

double roundTo2Significant(double x) {
  const double magnitude = std::pow(10.0, std::floor(std::log10(x)) - 1.0);
  return std::round(x / magnitude) * magnitude;
}

}  // namespace

ErrorStats computeStats(const std::vector<double>& values) {
  ErrorStats s;
  s.count = values.size();
  if (values.empty()) return s;
  const double n = static_cast<double>(values.size());
  double sum = 0.0, sum_sq = 0.0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  const size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

AteResult computeAte(const data::Trajectory& est_aligned, const data::Trajectory& gt) {
  checkMatched(est_aligned, gt);
  AteResult r;
  for (size_t i = 0; i < gt.size(); ++i) {
    r.t_ns.push_back(gt[i].t_ns);
    r.translation_m.push_back((gt[i].p_W_B - est_aligned[i].p_W_B).norm());
    r.rotation_deg.push_back(
        angleDeg((gt[i].q_W_B.conjugate() * est_aligned[i].q_W_B).toRotationMatrix()));
  }
  r.translation = computeStats(r.translation_m);
  r.rotation = computeStats(r.rotation_deg);
  return r;
}

double pathLength(const data::Trajectory& trajectory) {
  double length = 0.0;
  for (size_t i = 1; i < trajectory.size(); ++i)
    length += (trajectory[i].p_W_B - trajectory[i - 1].p_W_B).norm();
  return length;
}

std::vector<double> defaultRpeLengths(double path_length_m) {
  std::vector<double> lengths;
  if (!(path_length_m > 0.0)) return lengths;
  for (int percent = 10; percent <= 50; percent += 10)
    lengths.push_back(roundTo2Significant(path_length_m * percent / 100.0));
  return lengths;
}

std::vector<RpeResult> computeRpe(const data::Trajectory& est_aligned, const data::Trajectory& gt,
                                  const std::vector<double>& lengths_m, double length_tolerance) {
  checkMatched(est_aligned, gt);
  std::vector<double> travelled(gt.size(), 0.0);  // ground-truth distance from pose 0
  for (size_t i = 1; i < gt.size(); ++i)
    travelled[i] = travelled[i - 1] + (gt[i].p_W_B - gt[i - 1].p_W_B).norm();

  std::vector<RpeResult> results;
  for (double length : lengths_m) {
    if (!(length > 0.0))
      throw std::invalid_argument("RPE segment length must be > 0, got " + std::to_string(length));
    std::vector<double> trans_m, trans_pct, rot_deg, yaw_deg;
    for (size_t i = 0; i + 1 < gt.size(); ++i) {
      const double target = travelled[i] + length;
      auto it = std::lower_bound(travelled.begin() + static_cast<long>(i) + 1, travelled.end(),
                                 target - 1e-9 * length);
      if (it == travelled.end()) break;  // the path ends before i + L: no more segments
      size_t j = static_cast<size_t>(it - travelled.begin());
      if (j > i + 1 && target - travelled[j - 1] < travelled[j] - target) --j;
      const double distance = travelled[j] - travelled[i];
      if (!(std::abs(distance - length) <= length_tolerance * length) || !(distance > 0.0))
        continue;

      const Eigen::Isometry3d T_gt = isometry(gt[i]).inverse() * isometry(gt[j]);
      const Eigen::Isometry3d T_est = isometry(est_aligned[i]).inverse() * isometry(est_aligned[j]);
      const Eigen::Isometry3d E = T_gt.inverse() * T_est;
      const Eigen::Matrix3d R_W_j = gt[j].q_W_B.normalized().toRotationMatrix();
      const Eigen::Matrix3d E_W = R_W_j * E.linear() * R_W_j.transpose();
      const double e = E.translation().norm();
      trans_m.push_back(e);
      trans_pct.push_back(100.0 * e / distance);
      rot_deg.push_back(angleDeg(E.linear()));
      yaw_deg.push_back(std::abs(std::atan2(E_W(1, 0), E_W(0, 0))) * kRadToDeg);
    }
    RpeResult r;
    r.length_m = length;
    r.translation_m = computeStats(trans_m);
    r.translation_pct = computeStats(trans_pct);
    r.rotation_deg = computeStats(rot_deg);
    r.yaw_deg = computeStats(yaw_deg);
    results.push_back(r);
  }
  return results;
}

}  // namespace adugs::vio

#include "vio/eval/consistency.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdlib>

#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

// The ground-truth pose nearest to t within max_dt (gt sorted by time), or null.
const data::StampedPose* nearest(const data::Trajectory& gt, int64_t t_ns, int64_t max_dt_ns) {
  const auto after = std::lower_bound(gt.begin(), gt.end(), t_ns,
                                      [](const data::StampedPose& p, int64_t t) { return p.t_ns < t; });
  const data::StampedPose* best = nullptr;
  for (auto it : {after, after == gt.begin() ? gt.end() : std::prev(after)}) {
    if (it == gt.end() || std::llabs(it->t_ns - t_ns) > max_dt_ns) continue;
    if (!best || std::llabs(it->t_ns - t_ns) < std::llabs(best->t_ns - t_ns)) best = &*it;
  }
  return best;
}

// x^T P^-1 x for a positive definite P.
template <int N>
double mahalanobis(const Eigen::Matrix<double, N, 1>& x, const Eigen::Matrix<double, N, N>& P) {
  return x.dot(P.ldlt().solve(x));
}

}  // namespace

ConsistencyResult evaluateConsistency(const std::vector<RelativePoseEstimate>& estimates,
                                      const data::Trajectory& gt, int64_t max_dt_ns) {
  ConsistencyResult r;
  size_t within = 0;
  for (const RelativePoseEstimate& e : estimates) {
    const data::StampedPose* from = nearest(gt, e.t_from_ns, max_dt_ns);
    const data::StampedPose* to = nearest(gt, e.t_to_ns, max_dt_ns);
    if (!from || !to) continue;
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(e.covariance);
    if (llt.info() != Eigen::Success) continue;
    const Eigen::Matrix3d R_from = from->q_W_B.toRotationMatrix();
    const Eigen::Vector3d p_true = R_from.transpose() * (to->p_W_B - from->p_W_B);
    const Eigen::Quaterniond q_true = from->q_W_B.conjugate() * to->q_W_B;
    Eigen::Matrix<double, 6, 1> err;
    err.head<3>() = e.p_from_to - p_true;
    err.tail<3>() = quaternionLog(q_true.conjugate() * e.q_from_to);
    const double pose = err.dot(llt.solve(err));
    // The heading: rotation about gravity, whose direction in the newest body frame is
    // R_true_to^T z.
    const Eigen::Vector3d up = to->q_W_B.conjugate() * Eigen::Vector3d::UnitZ();
    const double yaw_error = up.dot(err.tail<3>());
    const double yaw_variance = up.dot(e.covariance.bottomRightCorner<3, 3>() * up);
    r.nees_pose += pose;
    r.nees_position += mahalanobis<3>(err.head<3>(), e.covariance.topLeftCorner<3, 3>());
    r.nees_yaw += yaw_error * yaw_error / yaw_variance;
    within += pose <= 12.592 ? 1 : 0;  // chi-square, 6 degrees of freedom, 95 %
    ++r.count;
  }
  if (r.count > 0) {
    const double n = static_cast<double>(r.count);
    r.nees_pose /= n;
    r.nees_position /= n;
    r.nees_yaw /= n;
    r.within_95 = static_cast<double>(within) / n;
  }
  return r;
}

}  // namespace adugs::vio

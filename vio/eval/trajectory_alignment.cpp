#include "vio/eval/trajectory_alignment.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace adugs::vio {
namespace {

// Below this ratio of singular values the cross-covariance is treated as rank deficient.
constexpr double kRankTolerance = 1e-10;

size_t usedCount(size_t size, int n) {
  return (n <= 0 || static_cast<size_t>(n) > size) ? size : static_cast<size_t>(n);
}

void checkPointSets(const std::vector<Eigen::Vector3d>& est,
                    const std::vector<Eigen::Vector3d>& gt) {
  if (est.size() != gt.size())
    throw std::invalid_argument("alignment: point sets differ in size (" +
                                std::to_string(est.size()) + " vs " + std::to_string(gt.size()) +
                                ")");
  if (est.empty()) throw std::invalid_argument("alignment: no points");
}

Eigen::Vector3d mean(const std::vector<Eigen::Vector3d>& points, size_t n) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) sum += points[i];
  return sum / static_cast<double>(n);
}

Eigen::Matrix3d rotationAboutZ(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The yaw theta maximising trace(Rz(theta) * H), i.e. minimising sum |g - Rz e|^2 when
// H = sum e g^T (or |Rz R_e - R_g|_F when H = R_e R_g^T).
double bestYaw(const Eigen::Matrix3d& H) {
  return std::atan2(H(0, 1) - H(1, 0), H(0, 0) + H(1, 1));
}

}  // namespace

AlignMode parseAlignMode(const std::string& name) {
  if (name == "se3") return AlignMode::kSe3;
  if (name == "sim3") return AlignMode::kSim3;
  if (name == "posyaw") return AlignMode::kPosYaw;
  if (name == "none") return AlignMode::kNone;
  throw std::invalid_argument("unknown alignment mode '" + name +
                              "' (use se3, sim3, posyaw or none)");
}

const char* alignModeName(AlignMode mode) {
  switch (mode) {
    case AlignMode::kSe3:
      return "se3";
    case AlignMode::kSim3:
      return "sim3";
    case AlignMode::kPosYaw:
      return "posyaw";
    case AlignMode::kNone:
      return "none";
  }
  return "?";
}

data::StampedPose SimilarityTransform::apply(const data::StampedPose& pose_E) const {
  data::StampedPose pose_G;
  pose_G.t_ns = pose_E.t_ns;
  pose_G.p_W_B = apply(pose_E.p_W_B);
  pose_G.q_W_B = (Eigen::Quaterniond(R_G_E) * pose_E.q_W_B).normalized();
  return pose_G;
}

data::Trajectory SimilarityTransform::apply(const data::Trajectory& trajectory_E) const {
  data::Trajectory out;
  out.reserve(trajectory_E.size());
  for (const data::StampedPose& pose : trajectory_E) out.push_back(apply(pose));
  return out;
}

std::vector<Association> associate(const data::Trajectory& est, const data::Trajectory& gt,
                                   int64_t max_dt_ns) {
  auto earlier = [](const data::StampedPose& a, const data::StampedPose& b) {
    return a.t_ns < b.t_ns;
  };
  if (!std::is_sorted(est.begin(), est.end(), earlier) ||
      !std::is_sorted(gt.begin(), gt.end(), earlier))
    throw std::invalid_argument("associate: trajectories must be sorted by time");

  std::vector<Association> pairs;
  std::vector<int64_t> pair_dt;
  for (size_t i = 0; i < est.size(); ++i) {
    const int64_t t = est[i].t_ns;
    auto it = std::lower_bound(gt.begin(), gt.end(), est[i], earlier);  // first gt >= t
    size_t best = gt.size();
    int64_t best_dt = 0;
    if (it != gt.end()) {
      best = static_cast<size_t>(it - gt.begin());
      best_dt = it->t_ns - t;
    }
    if (it != gt.begin() && (best == gt.size() || t - std::prev(it)->t_ns <= best_dt)) {
      best = static_cast<size_t>(it - gt.begin()) - 1;  // the earlier one wins a tie
      best_dt = t - std::prev(it)->t_ns;
    }
    if (best == gt.size() || best_dt > max_dt_ns) continue;
    // Nearest gt indices never decrease with i, so a taken gt pose can only be the last pair's.
    if (!pairs.empty() && pairs.back().gt_index == best) {
      if (best_dt < pair_dt.back()) {
        pairs.back().est_index = i;
        pair_dt.back() = best_dt;
      }
      continue;
    }
    pairs.push_back({i, best});
    pair_dt.push_back(best_dt);
  }
  return pairs;
}

SimilarityTransform alignUmeyama(const std::vector<Eigen::Vector3d>& est,
                                 const std::vector<Eigen::Vector3d>& gt, bool with_scale, int n) {
  checkPointSets(est, gt);
  const size_t count = usedCount(est.size(), n);
  const Eigen::Vector3d mean_e = mean(est, count);
  const Eigen::Vector3d mean_g = mean(gt, count);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // (1/n) sum (g - mean_g)(e - mean_e)^T
  double var_e = 0.0;                             // (1/n) sum |e - mean_e|^2
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d de = est[i] - mean_e;
    cov += (gt[i] - mean_g) * de.transpose();
    var_e += de.squaredNorm();
  }
  cov /= static_cast<double>(count);
  var_e /= static_cast<double>(count);

  Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  if (!(d(1) > kRankTolerance * d(0)))
    throw std::invalid_argument(
        "alignment is degenerate: the " + std::to_string(count) +
        " positions used are (nearly) collinear or identical; align on more "
        "poses or use --align none");
  Eigen::Vector3d s_diag(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0)
    s_diag(2) = -1.0;  // no mirror

  SimilarityTransform T;
  T.R_G_E = svd.matrixU() * s_diag.asDiagonal() * svd.matrixV().transpose();
  T.scale = with_scale ? d.dot(s_diag) / var_e : 1.0;
  T.t_G_E = mean_g - T.scale * T.R_G_E * mean_e;
  return T;
}

SimilarityTransform alignPositionYaw(const std::vector<Eigen::Vector3d>& est,
                                     const std::vector<Eigen::Vector3d>& gt, int n) {
  checkPointSets(est, gt);
  const size_t count = usedCount(est.size(), n);
  const Eigen::Vector3d mean_e = mean(est, count);
  const Eigen::Vector3d mean_g = mean(gt, count);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < count; ++i) H += (est[i] - mean_e) * (gt[i] - mean_g).transpose();
  SimilarityTransform T;
  T.R_G_E = rotationAboutZ(bestYaw(H));
  T.t_G_E = mean_g - T.R_G_E * mean_e;
  return T;
}

SimilarityTransform alignTrajectory(const data::Trajectory& est, const data::Trajectory& gt,
                                    AlignMode mode, int align_frames) {
  if (est.size() != gt.size())
    throw std::invalid_argument("alignment: matched trajectories differ in size");
  if (est.empty()) throw std::invalid_argument("alignment: no pose pairs");
  if (mode == AlignMode::kNone) return SimilarityTransform{};

  const size_t count = usedCount(est.size(), align_frames);
  if (count == 1 && mode != AlignMode::kSim3) {  // align the first poses, orientation included
    const Eigen::Matrix3d R_e = est[0].q_W_B.toRotationMatrix();
    const Eigen::Matrix3d R_g = gt[0].q_W_B.toRotationMatrix();
    SimilarityTransform T;
    T.R_G_E = mode == AlignMode::kSe3 ? Eigen::Matrix3d(R_g * R_e.transpose())
                                      : rotationAboutZ(bestYaw(R_e * R_g.transpose()));
    T.t_G_E = gt[0].p_W_B - T.R_G_E * est[0].p_W_B;
    return T;
  }
  if (mode == AlignMode::kSim3 && count < 3)
    throw std::invalid_argument("sim3 alignment needs at least 3 pose pairs, got " +
                                std::to_string(count));

  std::vector<Eigen::Vector3d> p_e, p_g;
  p_e.reserve(count);
  p_g.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    p_e.push_back(est[i].p_W_B);
    p_g.push_back(gt[i].p_W_B);
  }
  if (mode == AlignMode::kPosYaw) return alignPositionYaw(p_e, p_g);
  return alignUmeyama(p_e, p_g, mode == AlignMode::kSim3);
}

}  // namespace adugs::vio

#include "vio/init/sfm_bundle_adjustment.h"

#include <ceres/ceres.h>

namespace adugs::vio {
namespace {

// r = focal * (proj(R^T (X - p)) - observed); q (x y z w) is R_R_C.
struct SfmReprojectionCost {
  SfmReprojectionCost(const Eigen::Vector2d& observed, double focal)
      : observed_(observed), focal_(focal) {}

  template <typename T>
  bool operator()(const T* q_data, const T* p_data, const T* point_data, T* residual) const {
    Eigen::Map<const Eigen::Quaternion<T>> q(q_data);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(p_data);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> point(point_data);
    const Eigen::Matrix<T, 3, 1> p_C = q.conjugate() * (point - p);
    residual[0] = T(focal_) * (p_C.x() / p_C.z() - T(observed_.x()));
    residual[1] = T(focal_) * (p_C.y() / p_C.z() - T(observed_.y()));
    return true;
  }

  Eigen::Vector2d observed_;
  double focal_;
};

}  // namespace

bool bundleAdjust(SfmBundleProblem& problem, const SfmBundleOptions& options) {
  const size_t n = problem.poses.size();
  std::vector<Eigen::Quaterniond> rotations(n);
  std::vector<Eigen::Vector3d> positions(n);
  for (size_t k = 0; k < n; ++k) {
    rotations[k] = Eigen::Quaterniond(problem.poses[k].R_R_C).normalized();
    positions[k] = problem.poses[k].p_R_C;
  }
  std::map<int64_t, Eigen::Vector3d> points = problem.points;

  ceres::Problem ceres_problem;
  std::vector<bool> used(n, false);
  for (auto& [id, point] : points) {
    const auto it = problem.observations.find(id);
    if (it == problem.observations.end()) continue;
    for (const SfmObservation& obs : it->second) {
      if (obs.frame < 0 || static_cast<size_t>(obs.frame) >= n) continue;
      auto* cost = new ceres::AutoDiffCostFunction<SfmReprojectionCost, 2, 4, 3, 3>(
          new SfmReprojectionCost(obs.normalized, options.focal_px));
      ceres_problem.AddResidualBlock(cost, new ceres::HuberLoss(options.huber_px),
                                     rotations[obs.frame].coeffs().data(),
                                     positions[obs.frame].data(), point.data());
      used[obs.frame] = true;
    }
  }
  for (size_t k = 0; k < n; ++k) {
    if (!used[k]) continue;
    ceres_problem.SetManifold(rotations[k].coeffs().data(), new ceres::EigenQuaternionManifold);
    if (static_cast<int>(k) == problem.fixed_frame) {
      ceres_problem.SetParameterBlockConstant(rotations[k].coeffs().data());
      ceres_problem.SetParameterBlockConstant(positions[k].data());
    }
    // The pair frame keeps its distance to the reference (the scale) but not its direction: fixing
    // the whole position would freeze the essential matrix's baseline direction error into the
    // rotations (VINS-Mono fixes it; here it cost 0.2 - 1 deg with 0.5 px noise).
    if (static_cast<int>(k) == problem.fixed_position_frame &&
        static_cast<int>(k) != problem.fixed_frame)
      ceres_problem.SetManifold(positions[k].data(), new ceres::SphereManifold<3>);
  }
  if (ceres_problem.NumResidualBlocks() == 0) return false;

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &ceres_problem, &summary);
  if (summary.termination_type == ceres::FAILURE) return false;

  for (size_t k = 0; k < n; ++k) {
    if (!rotations[k].coeffs().allFinite() || !positions[k].allFinite()) return false;
  }
  for (const auto& [id, point] : points)
    if (!point.allFinite()) return false;
  for (size_t k = 0; k < n; ++k) {
    problem.poses[k].R_R_C = rotations[k].normalized().toRotationMatrix();
    problem.poses[k].p_R_C = positions[k];
  }
  problem.points = points;
  return true;
}

}  // namespace adugs::vio

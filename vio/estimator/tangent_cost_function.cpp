#include "vio/estimator/tangent_cost_function.h"

#include <algorithm>
#include <stdexcept>

namespace adugs::vio {
TangentCostFunction::TangentCostFunction(int num_residuals, std::initializer_list<int> block_sizes) {
  if (num_residuals > kMaxResiduals || block_sizes.size() > static_cast<size_t>(kMaxBlocks) ||
      std::any_of(block_sizes.begin(), block_sizes.end(),
                  [](int s) { return s != kPoseSize && s > kMaxTangentSize; }))
    throw std::invalid_argument("TangentCostFunction: residual or block too large");
  set_num_residuals(num_residuals);
  mutable_parameter_block_sizes()->assign(block_sizes);  // one allocation: thousands per keyframe
}

int TangentCostFunction::tangentSize(int block) const {
  const int size = parameter_block_sizes()[static_cast<size_t>(block)];
  return size == kPoseSize ? kPoseTangentSize : size;
}

bool TangentCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  if (!jacobians) return EvaluateTangent(parameters, residuals, nullptr);
  const int rows = num_residuals();
  const int n = static_cast<int>(parameter_block_sizes().size());
  double tangent[kMaxBlocks][kMaxResiduals * kMaxTangentSize];
  double* tangent_ptrs[kMaxBlocks];
  for (int k = 0; k < n; ++k) tangent_ptrs[k] = jacobians[k] ? tangent[k] : nullptr;
  if (!EvaluateTangent(parameters, residuals, tangent_ptrs)) return false;
  for (int k = 0; k < n; ++k) {
    if (!jacobians[k]) continue;
    const int size = parameter_block_sizes()[static_cast<size_t>(k)];
    if (size != kPoseSize) {
      std::copy(tangent[k], tangent[k] + rows * size, jacobians[k]);
      continue;
    }
    // Ambient = [J_dp, J_dtheta * d dtheta / d q] (pose_manifold.h).
    const Eigen::Matrix<double, 3, 4> lift = quaternionLiftJacobian(poseRotation(parameters[k]));
    for (int r = 0; r < rows; ++r) {
      const double* t = tangent[k] + r * kPoseTangentSize;
      double* a = jacobians[k] + r * kPoseSize;
      a[0] = t[0];
      a[1] = t[1];
      a[2] = t[2];
      for (int c = 0; c < 4; ++c) a[3 + c] = t[3] * lift(0, c) + t[4] * lift(1, c) + t[5] * lift(2, c);
    }
  }
  return true;
}

}  // namespace adugs::vio

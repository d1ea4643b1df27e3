#pragma once
// A factor whose Jacobians are derived in the tangent spaces of its blocks: pose blocks [p, q]
// (PoseManifold, tangent [dp, dtheta]) and Euclidean blocks. EvaluateTangent writes them as they
// are (row-major, rows x tangent size); Evaluate, what Ceres and the Jacobian checks call, lifts
// the pose blocks' to ambient coordinates (quaternionLiftJacobian, pose_manifold.h), so that Ceres'
// product with PlusJacobian gives the tangent Jacobian back. The window solver calls
// EvaluateTangent directly and skips both products.
#include <ceres/cost_function.h>

#include <initializer_list>

#include "vio/estimator/pose_manifold.h"

namespace adugs::vio {

class TangentCostFunction : public ceres::CostFunction {
 public:
  // tangent_jacobians[k] (may be null, or the array itself): rows x tangentSize(k), row-major.
  virtual bool EvaluateTangent(double const* const* parameters, double* residuals,
                               double** tangent_jacobians) const = 0;
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const final;

  // Blocks of 7 values are poses (tangent 6); others are Euclidean.
  int tangentSize(int block) const;

  // The largest residual and Euclidean block a factor may have (the IMU factor's 15 rows and
  // 9-value speed-bias blocks) and the most blocks: the fixed-capacity storage of Evaluate and of
  // the window solver, free of heap allocations per residual.
  static constexpr int kMaxResiduals = 15, kMaxTangentSize = 9, kMaxBlocks = 6;

 protected:
  TangentCostFunction(int num_residuals, std::initializer_list<int> block_sizes);
};

}  // namespace adugs::vio

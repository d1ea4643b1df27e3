#pragma once
// Ceres factor of one IMU preintegration between keyframes i and j (VINS-Mono's IMUFactor):
// 15 residuals r = S * preintegration.evaluate(...), S the upper Cholesky factor of the inverse
// covariance, on the parameter blocks
//   pose_i [p(3), q(4): x y z w] (PoseManifold), speed_bias_i [v_W(3), ba(3), bg(3)],
//   pose_j, speed_bias_j.
// Analytic Jacobians in the blocks' tangent spaces (tangent_cost_function.h; Ceres gets them
// lifted to the ambient quaternion coordinates, see pose_manifold.h).
#include <memory>

#include "vio/estimator/tangent_cost_function.h"
#include "vio/imu/imu_preintegration.h"

namespace adugs::vio {

constexpr int kSpeedBiasSize = 9;

class ImuFactor : public TangentCostFunction {
 public:
  // The whitening is computed here: rebuild the factor after repropagating.
  explicit ImuFactor(std::shared_ptr<const ImuPreintegration> preintegration);

  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** jacobians) const override;

  const ImuPreintegration& preintegration() const { return *preintegration_; }
  const Matrix15d& sqrtInformation() const { return sqrt_information_; }

 private:
  std::shared_ptr<const ImuPreintegration> preintegration_;
  Matrix15d sqrt_information_;
};

}  // namespace adugs::vio

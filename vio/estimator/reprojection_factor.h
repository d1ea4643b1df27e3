#pragma once
// Two-keyframe inverse-depth reprojection factors (VINS-Mono's ProjectionFactor and
// ProjectionTdFactor). A feature seen in host keyframe i at undistorted normalised coordinates
// pt_i = (x/z, y/z) with inverse depth lambda (along z of camera i) is mapped
//   p_Ci = [pt_i, 1] / lambda -> p_Bi = T_B_C p_Ci -> p_W = T_W_Bi p_Bi -> p_Bj -> p_Cj
// and compared with its observation pt_j in keyframe j on the normalised plane:
//   r = s * (p_Cj.xy / p_Cj.z - pt_j),   s = focal_px / pixel_sigma (sqrt information).
// Parameter blocks: pose_i, pose_j, T_B_C (all [p, q x y z w], PoseManifold), lambda (1)
// [, td (1): camera-IMU time offset in seconds, t_imu = t_cam + td].
// Analytic Jacobians in the blocks' tangent spaces (tangent_cost_function.h); behind-camera points
// are not rejected here (the estimator's job).
#include <Eigen/Core>

#include "vio/estimator/tangent_cost_function.h"

namespace adugs::vio {

// Sqrt information of a normalised-plane residual for a pixel standard deviation (VINS-Mono: 1.5 px).
inline double reprojectionSqrtInformation(double focal_px, double pixel_sigma = 1.5) {
  return focal_px / pixel_sigma;
}

class ReprojectionFactor : public TangentCostFunction {
 public:
  ReprojectionFactor(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                     double sqrt_information);
  // The same factor for another observation (ReprojectionFactorPool reuses factors).
  void setMeasurement(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                      double sqrt_information);
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** jacobians) const override;

 private:
  Eigen::Vector2d pt_i_, pt_j_;
  double sqrt_information_;
};

// With the time offset: each observation moves along its image velocity (normalised units per
// second, from the tracker) by the change of td since it was recorded with td_i / td_j:
//   pt_i(td) = pt_i - (td - td_i) vel_i,   pt_j(td) = pt_j - (td - td_j) vel_j.
class ReprojectionTdFactor : public TangentCostFunction {
 public:
  ReprojectionTdFactor(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                       const Eigen::Vector2d& vel_i, const Eigen::Vector2d& vel_j, double td_i,
                       double td_j, double sqrt_information);
  void setMeasurement(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                      const Eigen::Vector2d& vel_i, const Eigen::Vector2d& vel_j, double td_i,
                      double td_j, double sqrt_information);
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** jacobians) const override;

 private:
  Eigen::Vector2d pt_i_, pt_j_, vel_i_, vel_j_;
  double td_i_, td_j_;
  double sqrt_information_;
};

}  // namespace adugs::vio

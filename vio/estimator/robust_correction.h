#pragma once
// Ceres' Corrector (Triggs et al., "Bundle adjustment - a modern synthesis", sec. 4.3): for a
// robust cost rho(|r|^2) / 2, scales a residual r and its Jacobian J so that the Gauss-Newton
// model |r' + J' dx|^2 / 2 has rho's gradient and (first-order) curvature at r:
//   J' = sqrt(rho') (I - alpha r r^T / |r|^2) J,   r' = sqrt(rho') / (1 - alpha) r,
//   alpha = 1 - sqrt(1 + 2 |r|^2 rho'' / rho')   (0 where rho'' <= 0, e.g. Huber's outer part).
// Used where a residual block is linearised outside ceres::Solve: the window solver and the
// marginalisation.
#include <ceres/loss_function.h>

#include <cmath>

namespace adugs::vio {

struct RobustCorrection {
  double rho = 0;               // rho(|r|^2): the block's contribution to 2 x cost
  double residual_scaling = 1;  // r' = residual_scaling r
  double sqrt_rho1 = 1;         // J' = sqrt_rho1 (J - alpha_sq_norm r (r^T J))
  double alpha_sq_norm = 0;     // alpha / |r|^2
  // No loss, or inside a loss's quadratic part (Huber below its threshold): r and J unchanged.
  bool identity() const { return sqrt_rho1 == 1.0 && alpha_sq_norm == 0.0 && residual_scaling == 1.0; }
};

inline RobustCorrection robustCorrection(const ceres::LossFunction* loss, double sq_norm) {
  RobustCorrection c;
  if (!loss) {
    c.rho = sq_norm;
    return c;
  }
  double rho[3];
  loss->Evaluate(sq_norm, rho);
  c.rho = rho[0];
  c.sqrt_rho1 = std::sqrt(rho[1]);
  c.residual_scaling = c.sqrt_rho1;
  if (sq_norm > 0.0 && rho[2] > 0.0) {
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * sq_norm * rho[2] / rho[1]);
    c.residual_scaling = c.sqrt_rho1 / (1.0 - alpha);
    c.alpha_sq_norm = alpha / sq_norm;
  }
  return c;
}

}  // namespace adugs::vio

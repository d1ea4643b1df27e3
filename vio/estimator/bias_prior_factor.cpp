#include "vio/estimator/bias_prior_factor.h"

#include <cmath>

namespace adugs::vio {

bool gyroMeanAtRest(const std::vector<Eigen::Vector3d>& rates, double rate_hz, double gyro_noise_density,
                    Eigen::Vector3d* mean, Eigen::Vector3d* sigma) {
  const int n = static_cast<int>(rates.size());
  if (n < 2) return false;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& w : rates) sum += w;
  *mean = sum / n;
  Eigen::Vector3d squares = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& w : rates) squares += (w - *mean).cwiseAbs2();
  const Eigen::Vector3d spread = (squares / (n - 1)).cwiseSqrt();
  const double white = gyro_noise_density * std::sqrt(rate_hz);
  *sigma = spread.cwiseMax(white) / std::sqrt(static_cast<double>(n));
  return sigma->allFinite() && mean->allFinite() && sigma->minCoeff() > 0;
}

}  // namespace adugs::vio

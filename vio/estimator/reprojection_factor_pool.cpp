#include "vio/estimator/reprojection_factor_pool.h"

namespace adugs::vio {

const ReprojectionFactor* ReprojectionFactorPool::plain(const Eigen::Vector2d& pt_i,
                                                        const Eigen::Vector2d& pt_j,
                                                        double sqrt_information) {
  if (plain_used_ == plain_.size())
    plain_.push_back(std::make_unique<ReprojectionFactor>(pt_i, pt_j, sqrt_information));
  else
    plain_[plain_used_]->setMeasurement(pt_i, pt_j, sqrt_information);
  return plain_[plain_used_++].get();
}

const ReprojectionTdFactor* ReprojectionFactorPool::withTimeOffset(
    const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j, const Eigen::Vector2d& vel_i,
    const Eigen::Vector2d& vel_j, double td_i, double td_j, double sqrt_information) {
  if (with_td_used_ == with_td_.size())
    with_td_.push_back(
        std::make_unique<ReprojectionTdFactor>(pt_i, pt_j, vel_i, vel_j, td_i, td_j, sqrt_information));
  else
    with_td_[with_td_used_]->setMeasurement(pt_i, pt_j, vel_i, vel_j, td_i, td_j, sqrt_information);
  return with_td_[with_td_used_++].get();
}

}  // namespace adugs::vio

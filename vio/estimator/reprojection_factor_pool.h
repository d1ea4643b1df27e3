#pragma once
// Reprojection factors reused from one use to the next. A window solve, the outlier test and a
// marginalisation each take one factor per observation, thousands per keyframe; a new Ceres cost
// function each time was two heap allocations (the object and its block sizes) per observation
// and, with the other per-residual allocations, ~6 % of a run's CPU in malloc and free (heaptrack
// and perf on a 40 s hybrid flight).
#include <memory>
#include <vector>

#include "vio/estimator/reprojection_factor.h"

namespace adugs::vio {

class ReprojectionFactorPool {
 public:
  // Every factor handed out so far may be handed out again: call it where the previous user's
  // factors are no longer evaluated (the pool's users run one after the other).
  void reuseAll() { plain_used_ = with_td_used_ = 0; }

  const ReprojectionFactor* plain(const Eigen::Vector2d& pt_i, const Eigen::Vector2d& pt_j,
                                  double sqrt_information);
  const ReprojectionTdFactor* withTimeOffset(const Eigen::Vector2d& pt_i,
                                             const Eigen::Vector2d& pt_j,
                                             const Eigen::Vector2d& vel_i,
                                             const Eigen::Vector2d& vel_j, double td_i,
                                             double td_j, double sqrt_information);

 private:
  std::vector<std::unique_ptr<ReprojectionFactor>> plain_;
  std::vector<std::unique_ptr<ReprojectionTdFactor>> with_td_;
  size_t plain_used_ = 0, with_td_used_ = 0;
};

}  // namespace adugs::vio

#pragma once
// IMU-only dead reckoning: integrates every IMU sample from a known initial state taken from
// ground truth (pose, velocity and biases interpolated at the first IMU sample inside it).
// A baseline and a pipeline check, not an estimator: its error grows with t^2 to t^3.
#include <optional>
#include <vector>

#include "data/types.h"
#include "vio/imu/imu_integrator.h"

namespace adugs::vio {

// Ground-truth state at t, linearly interpolated (slerp for rotation); nullopt outside the range.
std::optional<NavState> interpolateGroundTruth(const std::vector<data::GroundTruthState>& gt,
                                               int64_t t_ns);

class ImuDeadReckoning {
 public:
  // gt must be sorted by time (as readGroundTruthStates returns it).
  explicit ImuDeadReckoning(std::vector<data::GroundTruthState> gt);

  // Samples must come in increasing time; samples before the ground truth starts are ignored.
  void addImu(const data::ImuSample& sample);

  // Pose at t (>= last sample time, zero-order hold of the last reading); nullopt before start.
  std::optional<data::StampedPose> poseAt(int64_t t_ns) const;

  bool started() const { return started_; }
  const NavState& state() const { return state_; }

 private:
  std::vector<data::GroundTruthState> gt_;
  bool started_ = false;
  NavState state_;
  data::ImuSample last_;
};

}  // namespace adugs::vio

#pragma once
// Hybrid mode: render the synthetic world along a GIVEN trajectory (EuRoC ground truth, body =
// IMU frame) and keep the GIVEN real IMU stream instead of simulating one.
#include <string>
#include <vector>

#include "data/sim/sim_trajectory.h"
#include "data/types.h"

namespace adugs::data {

// Poses between ground-truth rows: linear in position and velocity, slerp in rotation. Body rate
// and acceleration come from the neighbouring rows (used only to place objects, not for IMU).
class InterpolatedTrajectory : public SimTrajectory {
 public:
  // At least two states in strictly increasing time (std::invalid_argument otherwise). States
  // without velocity get central-difference velocities.
  explicit InterpolatedTrajectory(std::vector<GroundTruthState> states);

  SimBodyState stateAt(int64_t t_ns) const override;  // clamped to [start, end]
  int64_t startNs() const override { return states_.front().pose.t_ns; }
  int64_t endNs() const override { return states_.back().pose.t_ns; }
  const std::vector<GroundTruthState>& states() const { return states_; }

 private:
  std::vector<GroundTruthState> states_;
};

// Throws InputError (naming `path`) unless the samples span [start_ns, end_ns] without gaps longer
// than max_gap_ns.
void checkImuCoverage(const std::vector<ImuSample>& imu, const std::string& path, int64_t start_ns,
                      int64_t end_ns, int64_t max_gap_ns = 100000000);

}  // namespace adugs::data

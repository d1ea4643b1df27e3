#pragma once
// The navigation state at a later time, from a known state and the IMU samples since (strapdown,
// midpoint rule: vio/imu/imu_integrator.h). The masking stage runs a few frames ahead of the
// estimator: it carries the estimator's state after frame k - 3 to frames k - 1 and k to know where
// the camera went between them (the motion cue's translation), as OpenVINS and VINS-Mono propagate
// their last state to the newest IMU sample.
#include <cstdint>
#include <deque>

#include "data/types.h"
#include "vio/imu/imu_integrator.h"

namespace adugs::vio {

class ImuStatePredictor {
 public:
  // Samples must come in increasing time (the readers guarantee it); others throw
  // std::invalid_argument.
  void addImu(const data::ImuSample& sample);

  // `from` carried to to_ns through the buffered samples, with its biases; the IMU reading at both
  // ends interpolated between samples (held beyond the buffer). `from` itself when the buffer is
  // empty or to_ns <= from.t_ns.
  NavState predict(const NavState& from, int64_t to_ns) const;

  // Forgets samples no longer needed for predictions from t_ns or later.
  void dropBefore(int64_t t_ns);

  size_t size() const { return samples_.size(); }

 private:
  std::deque<data::ImuSample> samples_;
};

// Where the camera went between two states of its body: the displacement of the camera's centre
// from `before` to `after`, in the camera frame at `after` (T_B_C: camera to body).
Eigen::Vector3d cameraDisplacement(const NavState& before, const NavState& after, const Eigen::Isometry3d& T_B_C);

}  // namespace adugs::vio

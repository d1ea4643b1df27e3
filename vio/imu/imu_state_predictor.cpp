#include "vio/imu/imu_state_predictor.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "vio/imu/imu_preintegration.h"  // imuReadingAt

namespace adugs::vio {

void ImuStatePredictor::addImu(const data::ImuSample& sample) {
  if (!samples_.empty() && sample.t_ns <= samples_.back().t_ns)
    throw std::invalid_argument("ImuStatePredictor: IMU samples must come in increasing time");
  samples_.push_back(sample);
}

NavState ImuStatePredictor::predict(const NavState& from, int64_t to_ns) const {
  if (samples_.empty() || to_ns <= from.t_ns) return from;
  NavState state = from;
  data::ImuSample previous = imuReadingAt(samples_, from.t_ns);
  auto first = std::upper_bound(samples_.begin(), samples_.end(), from.t_ns,
                                [](int64_t t, const data::ImuSample& s) { return t < s.t_ns; });
  for (auto it = first; it != samples_.end() && it->t_ns < to_ns; ++it) {
    state = propagateMidpoint(state, previous, *it);
    previous = *it;
  }
  return propagateMidpoint(state, previous, imuReadingAt(samples_, to_ns));
}

void ImuStatePredictor::dropBefore(int64_t t_ns) {
  // Keep the last sample at or before t: the reading at t interpolates from it.
  while (samples_.size() > 1 && samples_[1].t_ns <= t_ns) samples_.pop_front();
}

Eigen::Vector3d cameraDisplacement(const NavState& before, const NavState& after, const Eigen::Isometry3d& T_B_C) {
  const Eigen::Vector3d c_before = before.p_W_B + before.q_W_B * T_B_C.translation();
  const Eigen::Vector3d c_after = after.p_W_B + after.q_W_B * T_B_C.translation();
  return T_B_C.rotation().transpose() * (after.q_W_B.conjugate() * (c_after - c_before));
}

}  // namespace adugs::vio

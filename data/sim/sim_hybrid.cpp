#include "data/sim/sim_hybrid.h"

#include <algorithm>
#include <stdexcept>

#include "data/formats/csv_reader.h"
#include "data/input_error.h"

namespace adugs::data {

InterpolatedTrajectory::InterpolatedTrajectory(std::vector<GroundTruthState> states)
    : states_(std::move(states)) {
  if (states_.size() < 2) throw std::invalid_argument("InterpolatedTrajectory: need two states");
  for (size_t i = 1; i < states_.size(); ++i)
    if (states_[i].pose.t_ns <= states_[i - 1].pose.t_ns)
      throw std::invalid_argument("InterpolatedTrajectory: time must increase");
  for (size_t i = 0; i < states_.size(); ++i) {
    if (states_[i].has_velocity_and_biases) continue;
    const size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, states_.size() - 1);
    states_[i].v_W = (states_[b].pose.p_W_B - states_[a].pose.p_W_B) /
                     nsToSec(states_[b].pose.t_ns - states_[a].pose.t_ns);
  }
}

SimBodyState InterpolatedTrajectory::stateAt(int64_t t_ns) const {
  t_ns = std::clamp(t_ns, startNs(), endNs());
  auto it = std::upper_bound(states_.begin(), states_.end(), t_ns,
                             [](int64_t t, const GroundTruthState& s) { return t < s.pose.t_ns; });
  const size_t j = std::min<size_t>(std::max<size_t>(static_cast<size_t>(it - states_.begin()), 1),
                                    states_.size() - 1);
  const GroundTruthState& a = states_[j - 1];
  const GroundTruthState& b = states_[j];
  const double dt = nsToSec(b.pose.t_ns - a.pose.t_ns);
  const double f = nsToSec(t_ns - a.pose.t_ns) / dt;
  SimBodyState s;
  s.t_ns = t_ns;
  s.p_W_B = a.pose.p_W_B + f * (b.pose.p_W_B - a.pose.p_W_B);
  s.q_W_B = a.pose.q_W_B.slerp(f, b.pose.q_W_B).normalized();
  s.v_W = a.v_W + f * (b.v_W - a.v_W);
  s.a_W = (b.v_W - a.v_W) / dt;
  const Eigen::AngleAxisd delta(a.pose.q_W_B.conjugate() * b.pose.q_W_B);
  s.omega_B = delta.angle() * delta.axis() / dt;
  return s;
}

void checkImuCoverage(const std::vector<ImuSample>& imu, const std::string& path, int64_t start_ns,
                      int64_t end_ns, int64_t max_gap_ns) {
  auto sec = [](int64_t t) { return std::to_string(nsToSec(t)); };
  if (imu.empty() || imu.front().t_ns > start_ns || imu.back().t_ns < end_ns)
    throw InputError(path, 0, "timestamp",
                     "the IMU stream does not cover the trajectory: IMU spans [" +
                         (imu.empty() ? std::string("-") : sec(imu.front().t_ns) + ", " + sec(imu.back().t_ns)) +
                         "] s, the trajectory needs [" + sec(start_ns) + ", " + sec(end_ns) + "] s");
  for (size_t i = 1; i < imu.size(); ++i)
    if (imu[i].t_ns > start_ns && imu[i - 1].t_ns < end_ns && imu[i].t_ns - imu[i - 1].t_ns > max_gap_ns)
      throw InputError(path, 0, "timestamp",
                       "gap of " + std::to_string(nsToSec(imu[i].t_ns - imu[i - 1].t_ns)) +
                           " s in the IMU stream at " + sec(imu[i - 1].t_ns) + " s");
}

}  // namespace adugs::data

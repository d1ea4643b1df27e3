#include "data/sim/sim_trajectory.h"

#include <cmath>
#include <stdexcept>

#include "data/types.h"

namespace adugs::data {

Eigen::Vector3d SineChannel::eval(double t) const {
  Eigen::Vector3d out(offset + rate * t, rate, 0.0);
  for (const Term& term : terms) {
    const double arg = term.freq * t + term.phase;
    const double s = std::sin(arg), c = std::cos(arg);
    out[0] += term.amp * s;
    out[1] += term.amp * term.freq * c;
    out[2] -= term.amp * term.freq * term.freq * s;
  }
  return out;
}

Eigen::Matrix3d eulerZyxToRotation(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

SineTrajectory::SineTrajectory(int64_t start_ns, int64_t end_ns,
                               std::array<SineChannel, 6> channels)
    : start_ns_(start_ns), end_ns_(end_ns), channels_(std::move(channels)) {
  if (end_ns_ <= start_ns_) throw std::invalid_argument("SineTrajectory: end must follow start");
}

SimBodyState SineTrajectory::stateAt(int64_t t_ns) const {
  // Seconds relative to the start keep full double precision even for EuRoC-size epochs.
  const double t = nsToSec(t_ns - start_ns_);
  Eigen::Vector3d e[6];
  for (int i = 0; i < 6; ++i) e[i] = channels_[i].eval(t);

  SimBodyState s;
  s.t_ns = t_ns;
  s.p_W_B = {e[kX][0], e[kY][0], e[kZ][0]};
  s.v_W = {e[kX][1], e[kY][1], e[kZ][1]};
  s.a_W = {e[kX][2], e[kY][2], e[kZ][2]};
  const double yaw = e[kYaw][0], pitch = e[kPitch][0], roll = e[kRoll][0];
  const double dyaw = e[kYaw][1], dpitch = e[kPitch][1], droll = e[kRoll][1];
  s.q_W_B = Eigen::Quaterniond(eulerZyxToRotation(yaw, pitch, roll)).normalized();
  // Body rate of R = Rz Ry Rx: each Euler rate expressed in the body frame.
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  s.omega_B = {droll - dyaw * sp, dpitch * cr + dyaw * cp * sr, -dpitch * sr + dyaw * cp * cr};
  return s;
}

}  // namespace adugs::data

#include "vio/imu/imu_dead_reckoning.h"

#include <algorithm>
#include <stdexcept>

namespace adugs::vio {

std::optional<NavState> interpolateGroundTruth(const std::vector<data::GroundTruthState>& gt,
                                               int64_t t_ns) {
  if (gt.empty() || t_ns < gt.front().pose.t_ns || t_ns > gt.back().pose.t_ns) return std::nullopt;
  auto after = std::lower_bound(gt.begin(), gt.end(), t_ns, [](const auto& s, int64_t t) {
    return s.pose.t_ns < t;
  });
  const auto& b = *after;
  const auto& a = after == gt.begin() ? b : *(after - 1);
  const double span = static_cast<double>(b.pose.t_ns - a.pose.t_ns);
  const double u = span > 0 ? static_cast<double>(t_ns - a.pose.t_ns) / span : 0.0;
  NavState s;
  s.t_ns = t_ns;
  s.p_W_B = (1 - u) * a.pose.p_W_B + u * b.pose.p_W_B;
  s.q_W_B = a.pose.q_W_B.slerp(u, b.pose.q_W_B).normalized();
  if (a.has_velocity_and_biases && b.has_velocity_and_biases) {
    s.v_W = (1 - u) * a.v_W + u * b.v_W;
    s.gyro_bias = (1 - u) * a.gyro_bias + u * b.gyro_bias;
    s.accel_bias = (1 - u) * a.accel_bias + u * b.accel_bias;
  } else if (span > 0) {
    s.v_W = (b.pose.p_W_B - a.pose.p_W_B) / data::nsToSec(b.pose.t_ns - a.pose.t_ns);
  }
  return s;
}

ImuDeadReckoning::ImuDeadReckoning(std::vector<data::GroundTruthState> gt) : gt_(std::move(gt)) {
  if (gt_.empty()) throw std::invalid_argument("IMU dead reckoning needs a ground-truth state");
}

void ImuDeadReckoning::addImu(const data::ImuSample& sample) {
  if (!started_) {
    if (const auto s = interpolateGroundTruth(gt_, sample.t_ns)) {
      state_ = *s;
      last_ = sample;
      started_ = true;
    }
    return;
  }
  state_ = propagateMidpoint(state_, last_, sample);
  last_ = sample;
}

std::optional<data::StampedPose> ImuDeadReckoning::poseAt(int64_t t_ns) const {
  if (!started_ || t_ns < last_.t_ns) return std::nullopt;
  NavState s = state_;
  if (t_ns > last_.t_ns) {
    data::ImuSample hold = last_;
    hold.t_ns = t_ns;
    s = propagateMidpoint(state_, last_, hold);
  }
  data::StampedPose pose;
  pose.t_ns = t_ns;
  pose.p_W_B = s.p_W_B;
  pose.q_W_B = s.q_W_B;
  return pose;
}

}  // namespace adugs::vio

#include "vio/imu/gyro_rotation_predictor.h"

#include <algorithm>
#include <iterator>

#include "vio/imu/so3.h"

namespace adugs::vio {

void GyroRotationPredictor::addImu(const data::ImuSample& sample) { samples_.push_back(sample); }

Eigen::Vector3d GyroRotationPredictor::rateAt(int64_t t_ns) const {
  auto after = std::upper_bound(samples_.begin(), samples_.end(), t_ns,
                                [](int64_t t, const data::ImuSample& s) { return t < s.t_ns; });
  if (after == samples_.begin()) return samples_.front().gyro;
  const data::ImuSample& a = *std::prev(after);
  if (after == samples_.end() || a.t_ns == t_ns) return a.gyro;
  const double w = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(after->t_ns - a.t_ns);
  return (1.0 - w) * a.gyro + w * after->gyro;
}

Eigen::Quaterniond GyroRotationPredictor::rotation(int64_t from_ns, int64_t to_ns,
                                                   const Eigen::Vector3d& gyro_bias) const {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (samples_.empty() || to_ns <= from_ns) return q;
  int64_t t_prev = from_ns;
  Eigen::Vector3d w_prev = rateAt(from_ns);
  auto step = [&](int64_t t, const Eigen::Vector3d& w) {
    const double dt = data::nsToSec(t - t_prev);
    q = q * quaternionExp((0.5 * (w_prev + w) - gyro_bias) * dt);
    t_prev = t;
    w_prev = w;
  };
  for (const data::ImuSample& s : samples_)
    if (s.t_ns > from_ns && s.t_ns < to_ns) step(s.t_ns, s.gyro);
  step(to_ns, rateAt(to_ns));
  return q.normalized();
}

void GyroRotationPredictor::dropBefore(int64_t t_ns) {
  // Keep the last sample at or before t: rateAt(t) interpolates from it.
  while (samples_.size() > 1 && samples_[1].t_ns <= t_ns) samples_.pop_front();
}

}  // namespace adugs::vio

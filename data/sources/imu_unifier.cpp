#include "data/sources/imu_unifier.h"

namespace adugs::data {

void ImuUnifier::addAccel(int64_t t_ns, const Eigen::Vector3d& accel) {
  accel_.push_back({t_ns, accel});
}

void ImuUnifier::addGyro(int64_t t_ns, const Eigen::Vector3d& gyro) {
  gyro_.push_back({t_ns, gyro});
}

bool ImuUnifier::pop(ImuSample* out) {
  while (!gyro_.empty() && !accel_.empty()) {
    const Stamped& g = gyro_.front();
    if (g.t_ns < accel_.front().t_ns) {  // before the first accelerometer sample we still hold
      ++unmatched_;
      gyro_.pop_front();
      continue;
    }
    // Keep only the last accelerometer sample at or before the gyro stamp, and those after it.
    while (accel_.size() >= 2 && accel_[1].t_ns <= g.t_ns) accel_.pop_front();
    const Stamped& a0 = accel_.front();
    if (a0.t_ns == g.t_ns) {
      out->accel = a0.v;
    } else if (accel_.size() >= 2) {
      const Stamped& a1 = accel_[1];
      const double s = static_cast<double>(g.t_ns - a0.t_ns) / static_cast<double>(a1.t_ns - a0.t_ns);
      out->accel = (1.0 - s) * a0.v + s * a1.v;
    } else {
      return false;  // wait for the accelerometer sample after the gyro stamp
    }
    out->t_ns = g.t_ns;
    out->gyro = g.v;
    gyro_.pop_front();
    return true;
  }
  return false;
}

void ImuUnifier::finish() {
  unmatched_ += gyro_.size();
  gyro_.clear();
}

}  // namespace adugs::data

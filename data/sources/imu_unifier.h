#pragma once
// Unites an accelerometer and a gyroscope published separately at different rates (RealSense
// D435i / OpenLORIS: accel ~250 Hz, gyro ~400 Hz) into IMU samples on the GYRO timestamps, the
// accelerometer linearly interpolated between its two samples around each gyro stamp, as
// realsense-ros' `unite_imu_method: linear_interpolation` and OpenLORIS' merge_imu_topics.py do.
//
// Both inputs must come in non-decreasing time (after stamp reordering). A gyro sample is released
// once an accelerometer sample at or after its stamp has arrived; gyro samples before the first or
// after the last accelerometer sample cannot be interpolated and are dropped (unmatched()).
#include <cstddef>
#include <cstdint>
#include <deque>

#include "data/types.h"

namespace adugs::data {

class ImuUnifier {
 public:
  void addAccel(int64_t t_ns, const Eigen::Vector3d& accel);
  void addGyro(int64_t t_ns, const Eigen::Vector3d& gyro);
  // The next united sample, if its accelerometer neighbours are known.
  bool pop(ImuSample* out);
  // End of input: the gyro samples still waiting can never be matched.
  void finish();

  size_t pendingGyro() const { return gyro_.size(); }
  size_t unmatched() const { return unmatched_; }

 private:
  struct Stamped {
    int64_t t_ns;
    Eigen::Vector3d v;
  };
  std::deque<Stamped> accel_, gyro_;
  size_t unmatched_ = 0;
};

}  // namespace adugs::data

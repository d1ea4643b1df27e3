#include "data/device/realsense_imu.h"

#include <cmath>

namespace adugs::data {

double realsenseGyroLsbDegPerSec(int real_bits) {
  if (real_bits == 16) return kRealsenseGyroLsbDeg16;
  if (real_bits == 32) return kRealsenseGyroLsbDeg32;
  return 0.0;
}

Eigen::Vector3d realsenseImuAxesToCamera(const Eigen::Vector3d& v) { return {-v.x(), v.y(), -v.z()}; }

Eigen::Vector3d realsenseAccelToBody(const Eigen::Vector3d& counts) {
  return realsenseImuAxesToCamera(counts * kRealsenseAccelLsb);
}

Eigen::Vector3d realsenseGyroToBody(const Eigen::Vector3d& counts, double gyro_lsb_deg_per_s) {
  return realsenseImuAxesToCamera(counts * (gyro_lsb_deg_per_s * M_PI / 180.0));
}

}  // namespace adugs::data

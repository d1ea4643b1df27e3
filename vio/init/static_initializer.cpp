#include "vio/init/static_initializer.h"

#include <cmath>
#include <sstream>

namespace adugs::vio {
namespace {

constexpr double kGravity = 9.81;

bool allFinite(const data::ImuSample& s) { return s.gyro.allFinite() && s.accel.allFinite(); }

// Per-axis population std of `values`.
Eigen::Vector3d axisStd(const std::vector<Eigen::Vector3d>& values) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& v : values) mean += v;
  mean /= static_cast<double>(values.size());
  Eigen::Vector3d var = Eigen::Vector3d::Zero();
  for (const auto& v : values) var += (v - mean).cwiseAbs2();
  return (var / static_cast<double>(values.size())).cwiseSqrt();
}

// Means of consecutive blocks of `smoothing_s` (a block closes when it spans smoothing_s);
// with smoothing_s <= 0 every sample is its own block.
void blockMeans(const std::vector<data::ImuSample>& samples, size_t first, double smoothing_s,
                std::vector<Eigen::Vector3d>* gyro, std::vector<Eigen::Vector3d>* accel) {
  Eigen::Vector3d sum_g = Eigen::Vector3d::Zero(), sum_a = Eigen::Vector3d::Zero();
  int count = 0;
  int64_t block_start = samples[first].t_ns;
  for (size_t i = first; i < samples.size(); ++i) {
    sum_g += samples[i].gyro;
    sum_a += samples[i].accel;
    ++count;
    const bool next_leaves_block =
        i + 1 == samples.size() || data::nsToSec(samples[i + 1].t_ns - block_start) >= smoothing_s;
    if (next_leaves_block) {
      // A trailing partial block shorter than half a block would add noise, not information.
      const bool partial = i + 1 == samples.size() &&
                           data::nsToSec(samples[i].t_ns - block_start) < 0.5 * smoothing_s;
      if (!partial || gyro->empty()) {
        gyro->push_back(sum_g / count);
        accel->push_back(sum_a / count);
      }
      sum_g.setZero();
      sum_a.setZero();
      count = 0;
      if (i + 1 < samples.size()) block_start = samples[i + 1].t_ns;
    }
  }
}

std::string formatVector(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(3);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

}  // namespace

Eigen::Matrix3d removeYaw(const Eigen::Matrix3d& R) {
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
}

Eigen::Quaterniond gravityAlignedOrientation(const Eigen::Vector3d& specific_force) {
  const Eigen::Matrix3d R =
      Eigen::Quaterniond::FromTwoVectors(specific_force, Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  // Rz keeps +z fixed, so removing the yaw keeps R * f along +z.
  Eigen::Quaterniond q(removeYaw(R));
  q.normalize();
  return q;
}

StaticInitResult initializeStatic(const std::vector<data::ImuSample>& imu_window,
                                  double mean_parallax_px, const StaticInitOptions& options) {
  StaticInitResult result;
  auto fail = [&result](const std::string& why) {
    result.stationary = false;
    result.reason = why;
    return result;
  };
  if (imu_window.empty()) return fail("no IMU samples in the static window");
  for (size_t i = 0; i < imu_window.size(); ++i) {
    if (!allFinite(imu_window[i])) return fail("non-finite IMU sample in the static window");
    if (i > 0 && imu_window[i].t_ns <= imu_window[i - 1].t_ns)
      return fail("IMU samples of the static window are not time-ordered");
  }
  // Only the last window_s seconds are inspected.
  const int64_t window_start = imu_window.back().t_ns - data::secToNs(options.window_s);
  size_t first = 0;
  while (first + 1 < imu_window.size() && imu_window[first].t_ns < window_start) ++first;
  const double span = data::nsToSec(imu_window.back().t_ns - imu_window[first].t_ns);
  const size_t count = imu_window.size() - first;
  if (count < static_cast<size_t>(std::max(options.min_samples, 2)) ||
      span < 0.8 * options.window_s) {
    std::ostringstream why;
    why << "IMU window too short for static initialization: " << count << " samples over " << span
        << " s (need " << options.min_samples << " over " << options.window_s << " s)";
    return fail(why.str());
  }

  Eigen::Vector3d sum_g = Eigen::Vector3d::Zero(), sum_a = Eigen::Vector3d::Zero();
  for (size_t i = first; i < imu_window.size(); ++i) {
    sum_g += imu_window[i].gyro;
    sum_a += imu_window[i].accel;
  }
  result.gyro_bias = sum_g / static_cast<double>(count);
  result.mean_accel = sum_a / static_cast<double>(count);

  std::vector<Eigen::Vector3d> gyro_blocks, accel_blocks;
  blockMeans(imu_window, first, options.smoothing_s, &gyro_blocks, &accel_blocks);
  result.smoothed_gyro_std = axisStd(gyro_blocks);
  result.smoothed_accel_std = axisStd(accel_blocks);

  if (!std::isfinite(mean_parallax_px)) return fail("non-finite image parallax");
  if (result.smoothed_gyro_std.maxCoeff() > options.max_gyro_std)
    return fail("gyro not quiet: smoothed std " + formatVector(result.smoothed_gyro_std) +
                " rad/s above " + std::to_string(options.max_gyro_std));
  if (result.smoothed_accel_std.maxCoeff() > options.max_accel_std)
    return fail("accelerometer not quiet: smoothed std " + formatVector(result.smoothed_accel_std) +
                " m/s^2 above " + std::to_string(options.max_accel_std));
  const double norm = result.mean_accel.norm();
  if (std::abs(norm - kGravity) > options.max_gravity_norm_error)
    return fail("mean specific force " + std::to_string(norm) + " m/s^2 is not gravity (9.81)");
  if (mean_parallax_px > options.max_parallax_px)
    return fail("image features move: mean parallax " + std::to_string(mean_parallax_px) +
                " px above " + std::to_string(options.max_parallax_px) + " px");

  result.q_W_B = gravityAlignedOrientation(result.mean_accel);
  result.stationary = true;
  result.reason.clear();
  return result;
}

}  // namespace adugs::vio

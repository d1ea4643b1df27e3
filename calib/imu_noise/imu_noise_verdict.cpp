#include "calib/imu_noise/imu_noise_verdict.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "calib/text_format.h"
#include "data/formats/yaml_options.h"

namespace adugs::calib {
namespace {

// Allan deviation at the cluster time nearest to tau, worst axis.
double deviationAt(const SensorNoise& n, double tau) {
  size_t best = 0;
  for (size_t i = 1; i < n.curve.tau.size(); ++i)
    if (std::abs(std::log(n.curve.tau[i] / tau)) < std::abs(std::log(n.curve.tau[best] / tau))) best = i;
  return n.curve.adev.empty() ? 0 : n.curve.adev[best].maxCoeff();
}

const std::string kStatic =
    "record with the IMU lying still (on a table, away from footsteps and fans), nothing moving "
    "it";
const std::string kHours = "record for hours (2 h or more): the random walk only shows at long cluster times";

}  // namespace

void readImuNoiseVerdictOptions(data::YamlOptionsReader& r, ImuNoiseVerdictOptions& o) {
  r.optional("max_static_gyro_adev", o.max_static_gyro_adev, 0.0, 1e6);
  r.optional("max_static_accel_adev", o.max_static_accel_adev, 0.0, 1e6);
  r.optional("failed_duration_s", o.failed_duration_s, 0.0, 1e9);
  r.optional("min_random_walk_visibility", o.min_random_walk_visibility, 0.0, 1e6);
}

double randomWalkVisibility(const SensorNoise& n, double duration_s) {
  if (!(n.random_walk > 0)) return 0;
  if (!(n.white > 0)) return std::numeric_limits<double>::infinity();  // random walk everywhere
  const double crossover = std::sqrt(3.0) * n.white / n.random_walk;
  return (duration_s / 10) / crossover;
}

CalibrationVerdict judgeImuNoise(const ImuNoiseResult& r, const ImuNoiseVerdictOptions& o) {
  CalibrationVerdict v;
  const double g1 = deviationAt(r.gyro, 1.0), a1 = deviationAt(r.accel, 1.0);
  if (g1 > o.max_static_gyro_adev || a1 > o.max_static_accel_adev)
    v.add(Verdict::kFailed, "not static",
          strprintf("the Allan deviation at tau = 1 s is %.3g rad/s (gyro) and %.3g m/s^2 (accel), "
                    "above %.3g and %.3g: the IMU moved, the curve is its motion, not its noise",
                    g1, a1, o.max_static_gyro_adev, o.max_static_accel_adev),
          kStatic);
  if (r.duration_s < o.failed_duration_s) {
    v.add(Verdict::kFailed, "duration",
          strprintf("%.0f s < %.0f s: the random walk's read-out at tau = 3 s lies beyond the "
                    "longest cluster time (a tenth of the recording)",
                    r.duration_s, o.failed_duration_s),
          kHours);
    return v;
  }
  for (const auto& [name, sensor] : {std::pair<const char*, const SensorNoise*>{"gyroscope", &r.gyro},
                                     std::pair<const char*, const SensorNoise*>{"accelerometer", &r.accel}}) {
    const double vis = randomWalkVisibility(*sensor, r.duration_s);
    if (vis < o.min_random_walk_visibility)
      v.add(Verdict::kWeak, "random walk",
            vis > 0 ? strprintf("%s: the longest cluster time (%.0f s) is %.1f x the crossover where "
                                "the random walk overtakes the white noise (< %.0f x): K rests on "
                                "a few long clusters",
                                name, r.duration_s / 10, vis, o.min_random_walk_visibility)
                    : strprintf("%s: no random walk found in %.0f s of data (K = 0 is a lower bound, "
                                "not a figure)",
                                name, r.duration_s),
            kHours);
  }
  return v;
}

}  // namespace adugs::calib

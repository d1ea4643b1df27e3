#include "data/sim/sim_imu.h"

#include <cmath>
#include <stdexcept>

#include "data/sim/sim_random.h"

namespace adugs::data {

namespace {

Eigen::Vector3d gaussian3(SimRng& rng) {
  const double x = rng.gaussian(), y = rng.gaussian(), z = rng.gaussian();
  return {x, y, z};
}

}  // namespace

ImuSample idealImu(const SimBodyState& state) {
  ImuSample s;
  s.t_ns = state.t_ns;
  s.gyro = state.omega_B;
  const Eigen::Vector3d g_W(0.0, 0.0, -kSimGravity);
  s.accel = state.q_W_B.toRotationMatrix().transpose() * (state.a_W - g_W);
  return s;
}

std::vector<SimImuRecord> synthesizeImu(const SimTrajectory& trajectory,
                                        const SimImuOptions& options) {
  if (!(options.rate_hz > 0)) throw std::invalid_argument("synthesizeImu: rate must be positive");
  const int64_t period_ns = secToNs(1.0 / options.rate_hz);
  const double dt = nsToSec(period_ns);
  const double gyro_sigma = options.gyro_noise_density / std::sqrt(dt);
  const double accel_sigma = options.accel_noise_density / std::sqrt(dt);
  const double gyro_walk = options.gyro_random_walk * std::sqrt(dt);
  const double accel_walk = options.accel_random_walk * std::sqrt(dt);

  SimRng rng = SimRng::derive(options.seed, 0x1A1);
  Eigen::Vector3d bg = options.initial_gyro_bias, ba = options.initial_accel_bias;
  std::vector<SimImuRecord> out;
  out.reserve(static_cast<size_t>((trajectory.endNs() - trajectory.startNs()) / period_ns + 1));
  for (int64_t t = trajectory.startNs(); t <= trajectory.endNs(); t += period_ns) {
    SimImuRecord r;
    r.truth = trajectory.stateAt(t);
    r.sample = idealImu(r.truth);
    r.gyro_bias = bg;
    r.accel_bias = ba;
    r.sample.gyro += bg;
    r.sample.accel += ba;
    if (options.noise) {
      // Draw order is fixed (gyro noise, accel noise, gyro walk, accel walk) for determinism.
      r.sample.gyro += gyro_sigma * gaussian3(rng);
      r.sample.accel += accel_sigma * gaussian3(rng);
      bg += gyro_walk * gaussian3(rng);
      ba += accel_walk * gaussian3(rng);
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace adugs::data

#include "data/sources/replay_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace adugs::data {

ReplaySource::ReplaySource(std::unique_ptr<data::SequenceSource> recorded, const ReplayTiming& timing)
    : recorded_(std::move(recorded)), timing_(timing), rng_(data::SimRng::derive(timing.seed, 17)) {
  if (!(timing_.speed > 0)) throw std::invalid_argument("ReplaySource: speed must be positive");
}

int64_t ReplaySource::deliveryTimeNs(const data::Measurement& m) {
  const int64_t t = m.timeNs();
  if (first_t_ < 0) first_t_ = t;
  if (m.isFrame()) {
    const double latency_ms = timing_.frame_latency_ms + rng_.uniform(-timing_.frame_jitter_ms, timing_.frame_jitter_ms);
    return t + data::secToNs(std::max(0.0, latency_ms) * 1e-3);
  }
  // The end of the IMU packet the sample falls in.
  const int64_t burst = std::max<int64_t>(1, data::secToNs(timing_.imu_burst_ms * 1e-3));
  return first_t_ + ((t - first_t_ + burst - 1) / burst) * burst;
}

bool ReplaySource::next(data::Measurement& m) {
  while (!clock_.stopped() && recorded_->next(m)) {
    const bool starting = first_t_ < 0;
    const int64_t delivery = std::max(deliveryTimeNs(m), last_delivery_);
    if (starting) wall_start_ = std::chrono::steady_clock::now();
    if (m.isFrame() && rng_.uniform() < timing_.frame_loss) {
      ++frames_lost_;  // lost on the way: the IMU goes on
      continue;
    }
    last_delivery_ = delivery;
    const auto due = wall_start_ + std::chrono::nanoseconds(static_cast<int64_t>(
                                       static_cast<double>(delivery - first_t_) / timing_.speed));
    return clock_.waitUntil(due);
  }
  return false;
}

void ReplaySource::stop() { clock_.stop(); }

data::SourceCounts ReplaySource::counts() const {
  data::SourceCounts c = recorded_->counts();
  c.frames_lost += frames_lost_;
  return c;
}

std::string ReplaySource::description() const {
  char timing[200];
  std::snprintf(timing, sizeof timing,
                " replayed at %gx sensor pace, D435i-like delivery (frames %g +- %g ms late, %g %% lost, IMU in %g ms "
                "packets, seed %llu)",
                timing_.speed, timing_.frame_latency_ms, timing_.frame_jitter_ms, 100.0 * timing_.frame_loss,
                timing_.imu_burst_ms, static_cast<unsigned long long>(timing_.seed));
  return recorded_->description() + timing;
}

}  // namespace adugs::data

#pragma once
// Playback controls around any source: `--start S --duration D` (the part of the sequence from S
// seconds after its first measurement, D seconds long; D <= 0 = to the end) and `--realtime`
// (measurements are released no faster than sensor time, for visual checks and live-like runs).
// Measurements before the window are read and discarded (sources stream, they cannot seek).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>

#include "data/sources/sequence_source.h"

namespace adugs::data {

class PlaybackControls : public SequenceSource {
 public:
  PlaybackControls(std::unique_ptr<SequenceSource> inner, int64_t start_ns, int64_t duration_ns, bool realtime)
      : inner_(std::move(inner)), start_ns_(start_ns), duration_ns_(duration_ns), realtime_(realtime) {}

  bool next(Measurement& m) override {
    while (!done_ && !stopped_ && inner_->next(m)) {
      if (first_t_ < 0) first_t_ = m.timeNs();
      const int64_t since_first = m.timeNs() - first_t_;
      if (since_first < start_ns_) continue;
      if (duration_ns_ > 0 && since_first > start_ns_ + duration_ns_) break;
      if (realtime_) pace(since_first - start_ns_);
      return true;
    }
    done_ = true;
    return false;
  }
  SourceCounts counts() const override { return inner_->counts(); }
  std::string description() const override { return inner_->description(); }
  bool isLive() const override { return inner_->isLive(); }
  std::string stopReason() const override { return inner_->stopReason(); }
  void stop() override {
    stopped_ = true;
    inner_->stop();
  }

 private:
  void pace(int64_t sensor_ns) {
    const auto now = std::chrono::steady_clock::now();
    if (!wall_started_) {
      wall_start_ = now;
      wall_started_ = true;
    }
    std::this_thread::sleep_until(wall_start_ + std::chrono::nanoseconds(sensor_ns));
  }

  std::unique_ptr<SequenceSource> inner_;
  int64_t start_ns_, duration_ns_;
  bool realtime_;
  int64_t first_t_ = -1;
  bool done_ = false;
  std::atomic<bool> stopped_{false};
  bool wall_started_ = false;
  std::chrono::steady_clock::time_point wall_start_;
};

}  // namespace adugs::data

#pragma once
// `adugs live --replay SEQ`: a recorded sequence delivered the way a live D435i delivers its
// measurements, so the live path runs (and is tested) without a camera. Same measurements, same
// stamps, but released at sensor pace (wall clock: the first measurement plus the sensor time
// since, divided by `speed`) with the sensor's delivery pattern:
//   frames  arrive frame_latency_ms after their stamp (exposure read-out + USB transfer), give or
//           take frame_jitter_ms (uniform); a fraction frame_loss never arrives (counted in
//           SourceCounts::frames_lost, as a device reports a sequence-number gap);
//   IMU     samples arrive in packets, one every imu_burst_ms of sensor time, as the HID
//           sensors hand them over.
// Measurements still come out in time order (what a live source merging its two streams does:
// an IMU sample stamped after a frame waits for that frame). Random draws come from `seed`, so
// which frames are lost is reproducible; the rest is wall-clock timing.
#include <chrono>
#include <memory>

#include "data/sim/sim_random.h"
#include "data/sources/paced_clock.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

struct ReplayTiming {
  double speed = 1.0;  // sensor seconds per wall second
  double frame_latency_ms = 15, frame_jitter_ms = 5;
  double frame_loss = 0.005;  // 1 frame in 200
  double imu_burst_ms = 10;
  uint64_t seed = 1;
};

class ReplaySource : public data::SequenceSource {
 public:
  ReplaySource(std::unique_ptr<data::SequenceSource> recorded, const ReplayTiming& timing);

  bool next(data::Measurement& m) override;  // waits until the measurement's delivery time
  data::SourceCounts counts() const override;
  std::string description() const override;
  bool isLive() const override { return true; }
  void stop() override;

  // Sensor time at which `m` is delivered (before keeping the time order), in ns; draws the
  // jitter for frames. Exposed for tests.
  int64_t deliveryTimeNs(const data::Measurement& m);

 private:
  std::unique_ptr<data::SequenceSource> recorded_;
  ReplayTiming timing_;
  data::SimRng rng_;
  int64_t first_t_ = -1;
  int64_t last_delivery_ = 0;  // keeps the output in time order
  size_t frames_lost_ = 0;
  std::chrono::steady_clock::time_point wall_start_;
  PacedClock clock_;
};

}  // namespace adugs::data

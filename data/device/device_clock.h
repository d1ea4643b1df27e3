#pragma once
// One clock for a device's measurements: the device stamps everything (frames, IMU samples) with
// its own free-running microsecond counter (32 bits on a RealSense D4xx: it wraps every 71.6
// minutes); the host sees each measurement some latency after it happened. DeviceClockMapper maps
// device time to the host's CLOCK_MONOTONIC by a running line fit over (device, host) pairs, as
// librealsense's global timestamp reader does, so that all streams of the device share one exact
// relative timing (the device's) on the host's time axis (which other sensors and the user share).
//
// The fit:
//   - pairs are kept per bucket_s of device time, the least delayed pair (smallest host - device
//     difference after the fitted rate) standing for its bucket; buckets older than window_s go;
//   - the slope (the device's rate error, a few tens of ppm, changing with temperature) is that
//     of the lower convex hull of the completed buckets' pairs at their mean time: of the lines
//     below every pair the one closest to them on average (the linear program of one-way clock
//     skew estimation, Moon et al. 1999), which buckets whose best pair was still delayed do not
//     tilt as they would a least-squares line; 1 until those pairs span min_span_s;
//   - the intercept puts the line on the lower envelope of the newest buckets holding at least
//     anchor_pairs pairs (at least the newest two buckets; half a second of IMU pairs, several
//     seconds of frame pairs): latencies are one-sided (a measurement never arrives before it
//     happened), so the envelope does not carry the mean latency or its jitter as a least-squares
//     intercept would, the more pairs the closer it gets to the smallest latency, and anchoring it
//     on recent pairs keeps the slope's error from being multiplied by a long lever arm.
// The mapped stamp is the host time of the event plus the minimum latency, a constant that the
// camera-IMU time offset absorbs; all the device's streams share it.
#include <cstddef>
#include <cstdint>
#include <deque>

namespace adugs::data {

// A free-running counter of `bits` bits unwrapped into an ever-growing count. Values may come out
// of order across streams (a frame stamped before the last IMU sample): a step back of less than
// half the counter's range is a step back, not a wrap.
class CounterUnwrapper {
 public:
  explicit CounterUnwrapper(int bits = 32);
  int64_t unwrap(uint64_t raw);
  bool started() const { return started_; }

 private:
  int bits_;
  bool started_ = false;
  int64_t newest_ = 0;  // the largest unwrapped value so far
};

struct DeviceClockOptions {
  double window_s = 30.0;   // pairs older than this (device time) are forgotten
  double bucket_s = 0.5;    // one pair per bucket goes into the fit
  double min_span_s = 1.0;  // below this span of the buckets' pairs the slope is taken as exactly 1
  int anchor_pairs = 800;   // the intercept's envelope: the newest buckets holding this many pairs
};

class DeviceClockMapper {
 public:
  explicit DeviceClockMapper(const DeviceClockOptions& options = {});

  // A measurement stamped `device_us` (unwrapped) was seen on the host at `host_ns`.
  void addPair(int64_t device_us, int64_t host_ns);
  bool ready() const { return count_ > 0; }
  // Host CLOCK_MONOTONIC time [ns] of device time `device_us` (unwrapped). Needs ready().
  int64_t toHostNs(int64_t device_us) const;
  // The fitted rate error of the device clock [ppm]: positive when it runs fast (0 before
  // min_span_s of pairs).
  double driftPpm() const;
  size_t pairs() const { return count_; }

 private:
  struct Pair {
    int64_t device_us;
    int64_t host_ns;
  };
  struct Bucket {
    int64_t index;  // floor((device_us - origin) / bucket_s)
    Pair best;      // its least delayed pair
    int pairs;      // how many pairs it saw
  };
  int64_t bucketOf(int64_t device_us) const;
  // Latency plus clock offset of a pair, less the fitted rate error: what a bucket keeps the least of.
  double delay(const Pair& p) const;
  void refit() const;

  DeviceClockOptions options_;
  std::deque<Bucket> buckets_;  // oldest first; the last one is being filled
  size_t count_ = 0;
  int64_t origin_device_us_ = 0, origin_host_ns_ = 0;  // keeps the fit's numbers small
  mutable bool dirty_ = true;
  mutable double slope_ = 0.0;      // ns of residual per us of device time (drift * 1e-3)
  mutable double intercept_ = 0.0;  // ns
};

}  // namespace adugs::data

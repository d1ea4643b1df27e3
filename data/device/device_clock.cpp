#include "data/device/device_clock.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace adugs::data {

CounterUnwrapper::CounterUnwrapper(int bits) : bits_(bits) {}

int64_t CounterUnwrapper::unwrap(uint64_t raw) {
  const uint64_t range = bits_ >= 64 ? 0 : (uint64_t{1} << bits_);
  const uint64_t mask = range - 1;
  if (range) raw &= mask;
  if (!started_) {
    started_ = true;
    newest_ = static_cast<int64_t>(raw);
    return newest_;
  }
  if (!range) {  // a 64-bit counter does not wrap in practice
    newest_ = std::max(newest_, static_cast<int64_t>(raw));
    return static_cast<int64_t>(raw);
  }
  // Signed distance from the newest value, modulo the range: within +-range/2.
  uint64_t forward = (raw - static_cast<uint64_t>(newest_)) & mask;
  int64_t delta = static_cast<int64_t>(forward);
  if (forward >= range / 2) delta -= static_cast<int64_t>(range);
  const int64_t value = newest_ + delta;
  newest_ = std::max(newest_, value);
  return value;
}

DeviceClockMapper::DeviceClockMapper(const DeviceClockOptions& options) : options_(options) {}

void DeviceClockMapper::addPair(int64_t device_us, int64_t host_ns) {
  if (count_ == 0) {
    origin_device_us_ = device_us;
    origin_host_ns_ = host_ns;
  }
  ++count_;
  dirty_ = true;
  const Pair pair{device_us, host_ns};
  const int64_t index = bucketOf(device_us);
  // Usually the newest bucket or a new one; a late pair (another stream's) goes to its own bucket.
  for (auto b = buckets_.rbegin(); b != buckets_.rend() && b->index >= index; ++b) {
    if (b->index != index) continue;
    ++b->pairs;
    if (delay(pair) < delay(b->best)) b->best = pair;
    return;
  }
  if (!buckets_.empty() && index < buckets_.back().index) return;  // its bucket has left the window
  buckets_.push_back({index, pair, 1});
  const int64_t window_us = std::llround(options_.window_s * 1e6);
  while (buckets_.size() > 2 && buckets_.front().best.device_us < device_us - window_us) buckets_.pop_front();
}

int64_t DeviceClockMapper::bucketOf(int64_t device_us) const {
  const int64_t bucket_us = std::max<int64_t>(1, std::llround(options_.bucket_s * 1e6));
  const int64_t dx = device_us - origin_device_us_;
  return dx >= 0 ? dx / bucket_us : -((-dx + bucket_us - 1) / bucket_us);  // floor division
}

double DeviceClockMapper::delay(const Pair& p) const {
  const int64_t dx = p.device_us - origin_device_us_;
  return static_cast<double>((p.host_ns - origin_host_ns_) - dx * 1000) - slope_ * static_cast<double>(dx);
}

void DeviceClockMapper::refit() const {
  if (!dirty_) return;
  dirty_ = false;
  // x: device us since the origin; y: host ns minus the nominal 1000 ns per us, since the origin.
  const auto x = [this](const Pair& p) { return static_cast<double>(p.device_us - origin_device_us_); };
  const auto y = [this](const Pair& p) {
    return static_cast<double>((p.host_ns - origin_host_ns_) - (p.device_us - origin_device_us_) * 1000);
  };
  // The slope from the completed buckets only (all but the newest): the bucket being filled may
  // hold a single, delayed pair at the end of the line, where it would tilt it most. It is the
  // slope of the lower convex hull at the pairs' mean device time.
  slope_ = 0.0;
  const size_t completed = buckets_.empty() ? 0 : buckets_.size() - 1;
  if (completed >= 2 && x(buckets_[completed - 1].best) - x(buckets_.front().best) >= options_.min_span_s * 1e6) {
    std::vector<std::pair<double, double>> hull;  // lower hull, x increasing (monotone chain)
    double mean_x = 0;
    for (size_t i = 0; i < completed; ++i) {
      const std::pair<double, double> q{x(buckets_[i].best), y(buckets_[i].best)};
      mean_x += q.first;
      while (hull.size() >= 2) {
        const auto& a = hull[hull.size() - 2];
        const auto& b = hull.back();
        // Keep b only if a -> b -> q turns left (b below the segment a-q).
        const double cross = (b.first - a.first) * (q.second - a.second) - (b.second - a.second) * (q.first - a.first);
        if (cross > 0) break;
        hull.pop_back();
      }
      hull.push_back(q);
    }
    mean_x /= static_cast<double>(completed);
    for (size_t i = 1; i < hull.size(); ++i) {
      if (hull[i].first >= mean_x || i + 1 == hull.size()) {
        slope_ = (hull[i].second - hull[i - 1].second) / (hull[i].first - hull[i - 1].first);
        break;
      }
    }
  }
  // The intercept: the lowest line (of that slope) through the newest buckets' best pairs, going
  // back until they hold anchor_pairs pairs, and at least two buckets.
  intercept_ = std::numeric_limits<double>::max();
  int pairs = 0;
  size_t used = 0;
  for (auto b = buckets_.rbegin(); b != buckets_.rend(); ++b) {
    if (used >= 2 && pairs >= options_.anchor_pairs) break;
    intercept_ = std::min(intercept_, y(b->best) - slope_ * x(b->best));
    pairs += b->pairs;
    ++used;
  }
}

int64_t DeviceClockMapper::toHostNs(int64_t device_us) const {
  refit();
  const int64_t dx = device_us - origin_device_us_;
  return origin_host_ns_ + dx * 1000 + std::llround(intercept_ + slope_ * static_cast<double>(dx));
}

double DeviceClockMapper::driftPpm() const {
  refit();
  // slope_ is the host's excess over 1000 ns per device us: negative when the device runs fast.
  return -slope_ * 1e3;  // 1 ns/us = 1000 ppm
}

}  // namespace adugs::data

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
  const int64_t bucket = bucketOf(device_us);
  if (has_current_ && bucket == current_bucket_) {
    if (delay(pair) < delay(current_)) current_ = pair;
    return;
  }
  if (has_current_ && bucket < current_bucket_) {  // a late pair of an older bucket: fold it in
    for (Pair& b : buckets_) {
      if (bucketOf(b.device_us) == bucket) {
        if (delay(pair) < delay(b)) b = pair;
        return;
      }
    }
    return;  // its bucket has left the window, or held no pair: too old to matter
  }
  if (has_current_) buckets_.push_back(current_);
  current_ = pair;
  current_bucket_ = bucket;
  has_current_ = true;
  const int64_t window_us = std::llround(options_.window_s * 1e6);
  while (!buckets_.empty() && buckets_.front().device_us < device_us - window_us) buckets_.pop_front();
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
  // The slope from the completed buckets only: the bucket being filled may hold a single, delayed
  // pair at the end of the line. It is the slope of the lower convex hull of the buckets' pairs
  // at their mean device time: of all lines below every pair, the one closest to them on average
  // (the linear program of one-way clock-skew estimation); buckets whose best pair was still
  // delayed lie above the hull and do not tilt it.
  slope_ = 0.0;
  const bool rate_known = buckets_.size() >= 2 && x(buckets_.back()) - x(buckets_.front()) >= options_.min_span_s * 1e6;
  if (rate_known) {
    std::vector<std::pair<double, double>> hull;  // lower hull, x increasing (monotone chain)
    double mean_x = 0;
    for (const Pair& p : buckets_) {
      const std::pair<double, double> q{x(p), y(p)};
      mean_x += q.first;
      while (hull.size() >= 2) {
        const auto& a = hull[hull.size() - 2];
        const auto& b = hull.back();
        // Drop b unless a -> b -> q turns left (b below the segment a-q).
        const double cross = (b.first - a.first) * (q.second - a.second) - (b.second - a.second) * (q.first - a.first);
        if (cross > 0) break;
        hull.pop_back();
      }
      hull.push_back(q);
    }
    mean_x /= static_cast<double>(buckets_.size());
    for (size_t i = 1; i < hull.size(); ++i) {
      if (hull[i].first >= mean_x || i + 1 == hull.size()) {
        slope_ = (hull[i].second - hull[i - 1].second) / (hull[i].first - hull[i - 1].first);
        break;
      }
    }
  }
  // The intercept: the lowest line through the newest buckets' pairs (the bucket filling among
  // them); only the newest two while the rate is unknown, the rate error growing with the distance.
  intercept_ = has_current_ ? y(current_) - slope_ * x(current_) : std::numeric_limits<double>::max();
  const int anchors = rate_known ? options_.anchor_buckets : std::min(2, options_.anchor_buckets);
  const size_t completed = static_cast<size_t>(std::max(0, anchors - (has_current_ ? 1 : 0)));
  for (size_t i = buckets_.size() - std::min(completed, buckets_.size()); i < buckets_.size(); ++i)
    intercept_ = std::min(intercept_, y(buckets_[i]) - slope_ * x(buckets_[i]));
}

int64_t DeviceClockMapper::toHostNs(int64_t device_us) const {
  refit();
  const int64_t dx = device_us - origin_device_us_;
  return origin_host_ns_ + dx * 1000 + std::llround(intercept_ + slope_ * static_cast<double>(dx));
}

double DeviceClockMapper::driftPpm() const {
  refit();
  return slope_ * 1e3;  // ns per us -> ppm: 1 ns/us = 1000 ppm
}

}  // namespace adugs::data

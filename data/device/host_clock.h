#pragma once
// The host's clocks in int64 nanoseconds. Live sources stamp measurements on CLOCK_MONOTONIC (as
// V4L2 buffer timestamps and uvcvideo's metadata are); other clocks only to convert from them.
#include <cstdint>
#include <climits>
#include <ctime>

namespace adugs::data {

inline int64_t hostClockNs(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

inline int64_t monotonicNs() { return hostClockNs(CLOCK_MONOTONIC); }

// Clock `id` minus CLOCK_MONOTONIC. Each read of `id` is bracketed by two monotonic reads and the
// tightest of a few brackets is kept: a thread preempted between two plain reads would put the
// preemption (tens of microseconds, more under a sanitizer) into every converted stamp.
inline int64_t clockMinusMonotonicNs(clockid_t id) {
  int64_t best_offset = 0, best_width = INT64_MAX;
  for (int attempt = 0; attempt < 8; ++attempt) {
    const int64_t before = monotonicNs();
    const int64_t other = hostClockNs(id);
    const int64_t after = monotonicNs();
    if (after - before < best_width) {
      best_width = after - before;
      best_offset = other - (before + (after - before) / 2);
    }
  }
  return best_offset;
}

}  // namespace adugs::data

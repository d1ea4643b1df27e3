#pragma once
// The host's clocks in int64 nanoseconds. Live sources stamp measurements on CLOCK_MONOTONIC (as
// V4L2 buffer timestamps and uvcvideo's metadata are); other clocks only to convert from them.
#include <cstdint>
#include <ctime>

namespace adugs::data {

inline int64_t hostClockNs(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

inline int64_t monotonicNs() { return hostClockNs(CLOCK_MONOTONIC); }

}  // namespace adugs::data

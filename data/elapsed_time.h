#pragma once
// Wall-clock milliseconds since a steady_clock time point: the per-stage timings every module
// reports (summary.yaml, the status line).
#include <chrono>

namespace adugs::data {

inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace adugs::data

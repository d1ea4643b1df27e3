// The device clock mapping (data/device/device_clock) against simulated devices, over many seeds:
// the worst and median of each run's largest error after a warm-up, and the fitted rate, per
// scenario (pair rate, latency jitter, rate error of the device clock).
//
//   bench_device_clock [--seeds N]
//
// Each run: a device counter starting 5 s before its 32-bit wrap, running `drift` fast, pairs every
// `period` of device time reaching the host a minimum latency plus jitter later; the error of a
// pair's own mapped stamp is (mapped - true host time - minimum latency). Not a Google Benchmark (a
// measurement tool): figures go to doc/d435i.md and doc/results.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "data/device/device_clock.h"

namespace {

using adugs::data::CounterUnwrapper;
using adugs::data::DeviceClockMapper;

struct Scenario {
  std::string name;
  int64_t period_us;
  double duration_s, min_latency_us, drift, warmup_s;
  std::function<double(std::mt19937&)> jitter_us;
};

struct Result {
  double max_error_us, drift_ppm;
};

Result run(const Scenario& s, unsigned seed) {
  std::mt19937 rng(seed);
  const int64_t wrap = int64_t{1} << 32;
  const int64_t d0 = wrap - 5'000'000;
  CounterUnwrapper unwrapper(32);
  DeviceClockMapper mapper;
  Result r{0, 0};
  for (int64_t d = d0; d < d0 + static_cast<int64_t>(s.duration_s * 1e6); d += s.period_us) {
    const int64_t device = unwrapper.unwrap(static_cast<uint64_t>(d % wrap));
    const double host = 1e12 + static_cast<double>(d - d0) * 1000.0 / (1.0 + s.drift);
    mapper.addPair(device, std::llround(host + (s.min_latency_us + s.jitter_us(rng)) * 1000.0));
    if (d - d0 < s.warmup_s * 1e6) continue;
    const double error = (static_cast<double>(mapper.toHostNs(device)) - host) / 1000.0 - s.min_latency_us;
    r.max_error_us = std::max(r.max_error_us, std::abs(error));
  }
  r.drift_ppm = mapper.driftPpm();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  unsigned seeds = 30;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--seeds" && i + 1 < argc) seeds = static_cast<unsigned>(std::atoi(argv[++i]));
    else {
      std::fprintf(stderr, "usage: bench_device_clock [--seeds N]\n");
      return 2;
    }
  }
  const auto uniform = [](double hi) { return [hi](std::mt19937& g) { return std::uniform_real_distribution<double>(0, hi)(g); }; };
  const auto heavy = [](std::mt19937& g) {  // exponential, mean 1 ms, one in 20 delayed 5-30 ms more
    std::uniform_real_distribution<double> u(0, 1);
    double j = std::exponential_distribution<double>(1.0 / 1000.0)(g);
    if (u(g) < 0.05) j += 5000 + 25000 * u(g);
    return j;
  };
  const std::vector<Scenario> scenarios = {
      {"IMU pairs 400 Hz, 0.8 ms + U(0, 2 ms), 50 ppm", 2500, 60, 800, 50e-6, 2, uniform(2000)},
      {"IMU pairs 400 Hz, 0.8 ms + U(0, 2 ms), -100 ppm", 2500, 60, 800, -100e-6, 2, uniform(2000)},
      {"IMU pairs 400 Hz, 0.8 ms + U(0, 10 ms) (loaded host), 50 ppm", 2500, 60, 800, 50e-6, 2, uniform(10000)},
      {"frame pairs 30 Hz, 3 ms + heavy tail, 50 ppm, from 6 s", 33333, 90, 3000, 50e-6, 6, heavy},
      {"frame pairs 30 Hz, 3 ms + heavy tail, 50 ppm, from 2 s", 33333, 90, 3000, 50e-6, 2, heavy},
  };
  std::printf("| scenario | seeds | max error, median of runs [us] | max error, worst run [us] | rate error found [ppm] (median, range) |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const Scenario& s : scenarios) {
    std::vector<double> errors, drifts;
    for (unsigned seed = 1; seed <= seeds; ++seed) {
      const Result r = run(s, seed);
      errors.push_back(r.max_error_us);
      drifts.push_back(r.drift_ppm);
    }
    std::sort(errors.begin(), errors.end());
    std::sort(drifts.begin(), drifts.end());
    std::printf("| %s | %u | %.0f | %.0f | %.1f (%.1f .. %.1f) |\n", s.name.c_str(), seeds, errors[errors.size() / 2],
                errors.back(), drifts[drifts.size() / 2], drifts.front(), drifts.back());
  }
  return 0;
}

#pragma once
// Portable deterministic random numbers for the simulator: the same seed gives the same bytes on
// every platform (std:: distributions are implementation-defined, so we draw our own).
#include <cmath>
#include <cstdint>
#include <random>

namespace adugs::data {

class SimRng {
 public:
  explicit SimRng(uint64_t seed) : engine_(seed) {}

  // Derives an independent stream for a named purpose (scene, objects, IMU noise, ...).
  static SimRng derive(uint64_t seed, uint64_t stream) {
    return SimRng(seed * 0x9E3779B97F4A7C15ull ^ (stream + 0x632BE59BD9B4E019ull));
  }

  uint64_t next() { return engine_(); }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int uniformInt(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(engine_() % static_cast<uint64_t>(hi - lo + 1));
  }
  // Standard normal (Box-Muller; the second value is cached).
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::mt19937_64 engine_;  // fully specified by the standard: portable sequence
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace adugs::data

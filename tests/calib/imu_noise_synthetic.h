#pragma once
// A static IMU for the Allan-variance tests and benchmark: per axis, white noise of density N
// plus a bias random walk of density K, sampled at rate_hz.
#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

namespace adugs::calib::synth {

inline std::vector<Eigen::Vector3d> staticImuAxes(double N, double K, double rate_hz, size_t n, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const double dt = 1.0 / rate_hz;
  std::vector<Eigen::Vector3d> out(n);
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    bias += K * std::sqrt(dt) * Eigen::Vector3d(g(rng), g(rng), g(rng));
    out[i] = bias + N / std::sqrt(dt) * Eigen::Vector3d(g(rng), g(rng), g(rng));
  }
  return out;
}

}  // namespace adugs::calib::synth

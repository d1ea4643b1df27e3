#pragma once
// The Kalman filter of one SORT track, with the adaptive measurement noise of doc/architecture.md
// ("The method").
//   state x = [cx, cy, w, h, vx, vy, vw, vh] (constant velocity, per frame), measurement z = [cx,
//   cy, w, h]. Process noise: white acceleration, sigma_accel_pos for (cx, cy), sigma_accel_size
//   for (w, h). Measurement noise: the last `window` innovations delta_k = z_k - H x_{k|k-1} give,
//   per component,
//     delta_RMSE = sqrt(mean(delta^2)),  R = diag(beta * erf(lambda * delta_RMSE)) + r_floor.
// erf saturates: a track whose detections jump around (occlusion, partial boxes) gets at most
// beta and leans on its prediction; a steady one gets a small R and follows its detections.
// r_floor keeps S invertible when the innovations vanish (a perfect detector).
#include <Eigen/Core>
#include <deque>
#include <functional>

#include "tracking/box.h"

namespace adugs::tracking {

struct AdaptiveNoiseOptions {
  int window = 10;                   // N innovations kept
  double beta_pos = 16.0;            // px^2: the largest R on cx, cy
  double beta_size = 16.0;           // px^2: the largest R on w, h
  double lambda = 0.25;              // 1/px: how fast R rises with the innovation RMSE
  double initial_rmse_px = 2.0;      // assumed RMSE before any innovation is seen
  double r_floor = 0.01;             // px^2
  double sigma_accel_pos = 1.0;      // px / frame^2
  double sigma_accel_size = 0.5;     // px / frame^2
  double initial_velocity_std = 10;  // px / frame, for a new track
};

// R for one component from its innovations (the formula above); exposed for tests.
double adaptiveMeasurementVariance(const std::deque<double>& innovations, double beta,
                                   double lambda, double initial_rmse, double r_floor);

class AdaptiveBoxFilter {
 public:
  using Vector8d = Eigen::Matrix<double, 8, 1>;
  using Matrix8d = Eigen::Matrix<double, 8, 8>;

  AdaptiveBoxFilter(const Box& first, const AdaptiveNoiseOptions& options = {});

  // Moves the state dt frames ahead; returns the predicted box (w, h kept >= 1 px).
  Box predict(double dt = 1.0);
  // Camera-motion compensation: moves the state as the image moved, `map` taking a pixel of the
  // previous image to the current one (e.g. the gyro's rotation through the camera model): the
  // centre is mapped, size and velocity go through the map's local Jacobian at the centre (central
  // differences over the box), and so does the covariance.
  void warp(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map);
  // Fuses a detection (after predict). Returns the innovation z - H x_pred.
  Eigen::Vector4d update(const Box& detection);

  Box box() const;
  const Vector8d& state() const { return x_; }
  const Matrix8d& covariance() const { return P_; }
  // The diagonal of R used by the last update (or the initial one).
  const Eigen::Vector4d& measurementVariance() const { return r_; }

 private:
  AdaptiveNoiseOptions options_;
  Vector8d x_;
  Matrix8d P_;
  Eigen::Vector4d r_;
  std::deque<double> innovations_[4];
};

}  // namespace adugs::tracking

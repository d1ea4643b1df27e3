#include "tracking/sort/adaptive_box_filter.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace adugs::tracking {

double adaptiveMeasurementVariance(const std::deque<double>& innovations, double beta,
                                   double lambda, double initial_rmse, double r_floor) {
  double rmse = initial_rmse;
  if (!innovations.empty()) {
    double sum_sq = 0;
    for (double d : innovations) sum_sq += d * d;
    rmse = std::sqrt(sum_sq / static_cast<double>(innovations.size()));
  }
  return beta * std::erf(lambda * rmse) + r_floor;
}

AdaptiveBoxFilter::AdaptiveBoxFilter(const Box& first, const AdaptiveNoiseOptions& options)
    : options_(options) {
  x_ << first.cx, first.cy, first.w, first.h, 0, 0, 0, 0;
  for (int c = 0; c < 4; ++c) {
    const double beta = c < 2 ? options_.beta_pos : options_.beta_size;
    r_(c) = adaptiveMeasurementVariance({}, beta, options_.lambda, options_.initial_rmse_px,
                                        options_.r_floor);
  }
  P_.setZero();
  P_.diagonal().head<4>() = r_;  // the first box is as good as a measurement
  P_.diagonal().tail<4>().setConstant(options_.initial_velocity_std *
                                      options_.initial_velocity_std);
}

Box AdaptiveBoxFilter::predict(double dt) {
  Matrix8d F = Matrix8d::Identity();
  F.topRightCorner<4, 4>() = dt * Eigen::Matrix4d::Identity();
  // Discrete white-acceleration noise: [dt^4/4, dt^3/2; dt^3/2, dt^2] * sigma^2 per component.
  Matrix8d Q = Matrix8d::Zero();
  for (int c = 0; c < 4; ++c) {
    const double s = c < 2 ? options_.sigma_accel_pos : options_.sigma_accel_size;
    const double q = s * s;
    Q(c, c) = q * dt * dt * dt * dt / 4;
    Q(c, c + 4) = Q(c + 4, c) = q * dt * dt * dt / 2;
    Q(c + 4, c + 4) = q * dt * dt;
  }
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + Q;
  // A box cannot shrink below a pixel: clamp, and stop the shrinking velocity.
  for (int c = 2; c < 4; ++c) {
    if (x_(c) < 1.0) {
      x_(c) = 1.0;
      x_(c + 4) = std::max(0.0, x_(c + 4));
    }
  }
  return box();
}

void AdaptiveBoxFilter::warp(const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& map) {
  const Eigen::Vector2d c(x_(0), x_(1));
  const double hx = std::max(1.0, 0.5 * x_(2)), hy = std::max(1.0, 0.5 * x_(3));
  Eigen::Matrix2d J;
  J.col(0) = (map(c + Eigen::Vector2d(hx, 0)) - map(c - Eigen::Vector2d(hx, 0))) / (2 * hx);
  J.col(1) = (map(c + Eigen::Vector2d(0, hy)) - map(c - Eigen::Vector2d(0, hy))) / (2 * hy);
  const double sw = J.col(0).norm(), sh = J.col(1).norm();  // an axis-aligned box keeps its axes
  Matrix8d T = Matrix8d::Zero();
  T.block<2, 2>(0, 0) = J;
  T(2, 2) = sw;
  T(3, 3) = sh;
  T.block<2, 2>(4, 4) = J;
  T(6, 6) = sw;
  T(7, 7) = sh;
  const Eigen::Vector2d mapped = map(c);
  x_ = T * x_;
  x_.head<2>() = mapped;
  P_ = T * P_ * T.transpose();
}

Eigen::Vector4d AdaptiveBoxFilter::update(const Box& detection) {
  const Eigen::Vector4d z(detection.cx, detection.cy, detection.w, detection.h);
  const Eigen::Vector4d innovation = z - x_.head<4>();
  for (int c = 0; c < 4; ++c) {
    auto& window = innovations_[c];
    window.push_back(innovation(c));
    while (static_cast<int>(window.size()) > options_.window) window.pop_front();
    const double beta = c < 2 ? options_.beta_pos : options_.beta_size;
    r_(c) = adaptiveMeasurementVariance(window, beta, options_.lambda, options_.initial_rmse_px,
                                        options_.r_floor);
  }
  // H = [I4 0]: S = P_pp + R, K = P_:p S^-1; Joseph form keeps P symmetric positive definite.
  const Eigen::Matrix4d S = P_.topLeftCorner<4, 4>() + Eigen::Matrix4d(r_.asDiagonal());
  const Eigen::Matrix<double, 8, 4> K = P_.leftCols<4>() * S.inverse();
  x_ += K * innovation;
  Eigen::Matrix<double, 4, 8> H = Eigen::Matrix<double, 4, 8>::Zero();
  H.leftCols<4>().setIdentity();
  const Matrix8d I_KH = Matrix8d::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * r_.asDiagonal() * K.transpose();
  return innovation;
}

Box AdaptiveBoxFilter::box() const { return {x_(0), x_(1), x_(2), x_(3)}; }

}  // namespace adugs::tracking

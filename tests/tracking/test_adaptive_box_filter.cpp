#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "tracking/sort/adaptive_box_filter.h"

namespace adugs::tracking {
namespace {

TEST(AdaptiveNoise, HandWorkedErfFormula) {
  // Innovations 3 and 4: RMSE = sqrt((9 + 16) / 2) = 3.5355339; lambda 0.2 -> erf(0.70710678)
  // = 0.68268949 (the one-sigma probability); beta 10 -> R = 6.8268949, plus the floor.
  const std::deque<double> window{3.0, -4.0};
  EXPECT_NEAR(adaptiveMeasurementVariance(window, 10.0, 0.2, 2.0, 0.0), 6.8268949, 1e-6);
  EXPECT_NEAR(adaptiveMeasurementVariance(window, 10.0, 0.2, 2.0, 0.5), 7.3268949, 1e-6);
  // No innovations yet: the assumed RMSE, 2 px -> 10 erf(0.4) = 4.2839236.
  EXPECT_NEAR(adaptiveMeasurementVariance({}, 10.0, 0.2, 2.0, 0.0), 4.2839236, 1e-6);
  // Saturation: huge innovations give beta, never more.
  EXPECT_NEAR(adaptiveMeasurementVariance({500.0, -800.0}, 10.0, 0.2, 2.0, 0.0), 10.0, 1e-12);
  // Perfect detections: only the floor is left.
  EXPECT_DOUBLE_EQ(adaptiveMeasurementVariance({0.0, 0.0}, 10.0, 0.2, 2.0, 0.01), 0.01);
}

TEST(AdaptiveBoxFilter, LearnsConstantVelocityAndPredictsThroughAGap) {
  AdaptiveBoxFilter f(Box{100, 200, 40, 80});
  for (int k = 1; k <= 30; ++k) {
    f.predict();
    f.update(Box{100 + 3.0 * k, 200 - 1.0 * k, 40, 80});
  }
  EXPECT_NEAR(f.state()(4), 3.0, 0.05);
  EXPECT_NEAR(f.state()(5), -1.0, 0.05);
  // Five frames without detections: the prediction continues the motion.
  Box b;
  for (int k = 0; k < 5; ++k) b = f.predict();
  EXPECT_NEAR(b.cx, 100 + 3.0 * 35, 0.5);
  EXPECT_NEAR(b.cy, 200 - 1.0 * 35, 0.5);
  EXPECT_NEAR(b.w, 40, 0.2);
  // Perfect detections drive R down to (nearly) the floor.
  EXPECT_LT(f.measurementVariance()(0), 0.2);
}

TEST(AdaptiveBoxFilter, JumpyDetectionsRaiseRAndAreTrustedLess) {
  AdaptiveNoiseOptions o;
  AdaptiveBoxFilter steady(Box{0, 0, 50, 50}, o), jumpy(Box{0, 0, 50, 50}, o);
  for (int k = 1; k <= 20; ++k) {
    steady.predict();
    jumpy.predict();
    steady.update(Box{0, 0, 50, 50});
    jumpy.update(Box{(k % 2 ? 12.0 : -12.0), 0, 50, 50});  // +-12 px detection noise
  }
  EXPECT_GT(jumpy.measurementVariance()(0), 0.9 * o.beta_pos);  // erf(0.25 * ~12) ~ 1
  EXPECT_LT(steady.measurementVariance()(0), 0.1);
  // The jumpy track's estimate stays near the true centre instead of following the detections.
  EXPECT_LT(std::abs(jumpy.box().cx), 6.0);
  // The covariance stays symmetric and positive definite.
  const auto& P = jumpy.covariance();
  EXPECT_LT((P - P.transpose()).norm(), 1e-9);
  EXPECT_GT(P.eigenvalues().real().minCoeff(), 0.0);
}

// The fixed-R ablation (`adugs track --fixed-noise`, run config `dynamic: noise: fixed`): lambda
// 1e6 saturates the erf, so R stays at beta (plus the floor) where the adaptive R follows the
// innovations of the detections' +-0.5 px noise (RMSE about 0.9 px) down to about 3.7 px^2.
TEST(AdaptiveBoxFilter, FixedNoiseKeepsRAtBeta) {
  AdaptiveNoiseOptions adaptive, fixed;
  fixed.lambda = 1e6;
  AdaptiveBoxFilter a(Box{0, 0, 50, 50}, adaptive), f(Box{0, 0, 50, 50}, fixed);
  for (int k = 1; k <= 20; ++k) {
    a.predict();
    f.predict();
    const Box detection{(k % 2 ? 0.5 : -0.5), 0, 50, 50};
    a.update(detection);
    f.update(detection);
  }
  EXPECT_NEAR(f.measurementVariance()(0), fixed.beta_pos + fixed.r_floor, 1e-9);
  EXPECT_LT(a.measurementVariance()(0), 0.3 * adaptive.beta_pos);
  EXPECT_GT(a.measurementVariance()(0), 0.5);
}

TEST(AdaptiveBoxFilter, SizeNeverCollapses) {
  AdaptiveBoxFilter f(Box{10, 10, 4, 4});
  for (int k = 1; k <= 5; ++k) {
    f.predict();
    f.update(Box{10, 10, 4.0 - 0.7 * k, 4.0 - 0.7 * k});
  }
  for (int k = 0; k < 20; ++k) {
    const Box b = f.predict();
    EXPECT_GE(b.w, 1.0);
    EXPECT_GE(b.h, 1.0);
  }
}

}  // namespace
}  // namespace adugs::tracking

namespace adugs::tracking {
namespace {

// Camera-motion compensation by hand: a shift moves only the centre; a zoom by 2 about the origin
// doubles the centre, the size, the velocity and the position/size standard deviations.
TEST(AdaptiveBoxFilter, WarpMovesTheStateAsTheImageMoved) {
  AdaptiveBoxFilter f(Box{100, 50, 20, 40});
  f.predict();
  f.update(Box{104, 50, 20, 40});  // some velocity
  const AdaptiveBoxFilter::Vector8d x0 = f.state();
  const AdaptiveBoxFilter::Matrix8d P0 = f.covariance();
  AdaptiveBoxFilter shifted = f;
  shifted.warp([](const Eigen::Vector2d& p) { return Eigen::Vector2d(p + Eigen::Vector2d(30, -5)); });
  EXPECT_NEAR(shifted.state()(0), x0(0) + 30, 1e-9);
  EXPECT_NEAR(shifted.state()(1), x0(1) - 5, 1e-9);
  EXPECT_NEAR((shifted.state().tail<6>() - x0.tail<6>()).norm(), 0, 1e-9);
  EXPECT_NEAR((shifted.covariance() - P0).norm(), 0, 1e-9);
  AdaptiveBoxFilter zoomed = f;
  zoomed.warp([](const Eigen::Vector2d& p) { return Eigen::Vector2d(2 * p); });
  EXPECT_NEAR((zoomed.state() - 2 * x0).norm(), 0, 1e-9);
  EXPECT_NEAR((zoomed.covariance() - 4 * P0).norm(), 0, 1e-9 * P0.norm());
}

}  // namespace
}  // namespace adugs::tracking

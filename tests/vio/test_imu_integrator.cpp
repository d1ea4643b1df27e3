#include <gtest/gtest.h>

#include <cmath>

#include "vio/imu/imu_integrator.h"

namespace adugs::vio {
namespace {

TEST(QuaternionExp, HandWorkedQuarterTurnAndSmallAngle) {
  const Eigen::Quaterniond q = quaternionExp(Eigen::Vector3d(0, 0, M_PI / 2));
  EXPECT_TRUE((q * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  const Eigen::Quaterniond s = quaternionExp(Eigen::Vector3d(1e-14, 0, 0));
  EXPECT_NEAR(s.norm(), 1.0, 1e-15);
  EXPECT_NEAR(s.x(), 0.5e-14, 1e-20);
}

TEST(PropagateMidpoint, StationaryLevelImuStaysPut) {
  NavState s;
  data::ImuSample a, b;
  a.accel = b.accel = Eigen::Vector3d(0, 0, 9.81);  // specific force at rest, z up
  b.t_ns = 5'000'000;
  for (int i = 0; i < 2000; ++i) {
    a.t_ns = s.t_ns;
    b.t_ns = s.t_ns + 5'000'000;
    s = propagateMidpoint(s, a, b);
  }
  EXPECT_LT(s.p_W_B.norm(), 1e-9);
  EXPECT_LT(s.v_W.norm(), 1e-9);
}

// Body turning at constant rate w about z while moving on the circle p = r (cos wt, sin wt, 0);
// the IMU readings come from the analytic motion: f_B = R^T (a_W - g_W), omega_B = (0, 0, w).
TEST(PropagateMidpoint, ReproducesAnalyticCircleToSecondOrder) {
  const double r = 2.0, w = 0.8, dt = 0.005;
  auto pose = [&](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()));
  };
  auto imuAt = [&](double t) {
    data::ImuSample s;
    s.t_ns = data::secToNs(t);
    s.gyro = Eigen::Vector3d(0, 0, w);
    const Eigen::Vector3d a_W(-r * w * w * std::cos(w * t), -r * w * w * std::sin(w * t), 0);
    s.accel = pose(t).inverse() * (a_W - gravityWorld());
    return s;
  };
  NavState s;
  s.p_W_B = Eigen::Vector3d(r, 0, 0);
  s.v_W = Eigen::Vector3d(0, r * w, 0);
  const int steps = 2000;  // 10 s, more than one full circle
  for (int k = 0; k < steps; ++k) s = propagateMidpoint(s, imuAt(k * dt), imuAt((k + 1) * dt));
  const double t = steps * dt;
  const Eigen::Vector3d p_true(r * std::cos(w * t), r * std::sin(w * t), 0);
  EXPECT_LT((s.p_W_B - p_true).norm(), 2e-3);
  EXPECT_LT(s.q_W_B.angularDistance(pose(t)), 1e-9);
  // Halving dt must cut the error by about 4 (second-order method).
  NavState h;
  h.p_W_B = Eigen::Vector3d(r, 0, 0);
  h.v_W = Eigen::Vector3d(0, r * w, 0);
  for (int k = 0; k < 2 * steps; ++k)
    h = propagateMidpoint(h, imuAt(k * dt / 2), imuAt((k + 1) * dt / 2));
  const double ratio = (s.p_W_B - p_true).norm() / (h.p_W_B - p_true).norm();
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.0);
}

TEST(PropagateMidpoint, RejectsNonIncreasingTimestamps) {
  data::ImuSample a, b;
  a.t_ns = b.t_ns = 10;
  EXPECT_THROW(propagateMidpoint(NavState{}, a, b), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio

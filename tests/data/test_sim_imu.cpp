// Synthetic trajectory derivatives and IMU: the IMU integrates back to the ground truth, and the
// noise has the statistics the densities promise.
#include <cmath>

#include <gtest/gtest.h>

#include "data/sim/sim_imu.h"
#include "data/sim/sim_trajectory.h"

namespace adugs::data {
namespace {

SineTrajectory testTrajectory(double duration_s = 10.0) {
  std::array<SineChannel, 6> ch;
  ch[SineTrajectory::kX] = {0.5, 0.0, {{1.5, 0.7, 0.1}, {0.3, 2.1, 1.0}}};
  ch[SineTrajectory::kY] = {-0.2, 0.0, {{1.2, 0.9, 1.3}, {0.2, 1.7, 0.4}}};
  ch[SineTrajectory::kZ] = {1.4, 0.0, {{0.25, 1.1, 0.2}}};
  ch[SineTrajectory::kYaw] = {0.3, 0.2, {{0.8, 0.5, 0.0}, {0.1, 2.3, 0.5}}};
  ch[SineTrajectory::kPitch] = {0.0, 0.0, {{0.15, 1.3, 0.3}}};
  ch[SineTrajectory::kRoll] = {0.05, 0.0, {{0.12, 1.9, 1.1}}};
  const int64_t t0 = 1403715273262142976;  // EuRoC-size epoch: exercises time precision
  return SineTrajectory(t0, t0 + secToNs(duration_s), ch);
}

Eigen::Vector3d logSo3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

TEST(SimTrajectory, DerivativesMatchFiniteDifferences) {
  const SineTrajectory traj = testTrajectory();
  const int64_t h_ns = 10000;  // 10 us
  const double h = nsToSec(h_ns);
  for (double ts : {0.5, 3.3, 7.9}) {
    const int64_t t = traj.startNs() + secToNs(ts);
    const SimBodyState s0 = traj.stateAt(t - h_ns), s1 = traj.stateAt(t), s2 = traj.stateAt(t + h_ns);
    EXPECT_LT(((s2.p_W_B - s0.p_W_B) / (2 * h) - s1.v_W).norm(), 1e-6);
    EXPECT_LT(((s2.v_W - s0.v_W) / (2 * h) - s1.a_W).norm(), 1e-6);
    const Eigen::Matrix3d R0 = s0.q_W_B.toRotationMatrix(), R2 = s2.q_W_B.toRotationMatrix();
    const Eigen::Vector3d omega_fd = logSo3(R0.transpose() * R2) / (2 * h);
    EXPECT_LT((omega_fd - s1.omega_B).norm(), 1e-6);
  }
}

// State derivative for RK4: p' = v, v' = R (a_m - b_a) + g, R' = R [w_m - b_g]x (quaternion form).
struct NavState {
  Eigen::Vector3d p, v;
  Eigen::Quaterniond q;
};

NavState derivative(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel) {
  NavState d;
  d.p = x.v;
  d.v = x.q.toRotationMatrix() * accel + Eigen::Vector3d(0, 0, -kSimGravity);
  const Eigen::Quaterniond w(0, gyro.x(), gyro.y(), gyro.z());
  d.q.coeffs() = 0.5 * (x.q * w).coeffs();
  return d;
}

NavState add(const NavState& x, const NavState& d, double h) {
  NavState y;
  y.p = x.p + h * d.p;
  y.v = x.v + h * d.v;
  y.q.coeffs() = x.q.coeffs() + h * d.q.coeffs();
  return y;
}

TEST(SimImu, NoiseFreeImuIntegratesToGroundTruth) {
  const SineTrajectory traj = testTrajectory(10.0);
  SimImuOptions opt;
  opt.noise = false;
  opt.initial_gyro_bias = {0.01, -0.02, 0.015};
  opt.initial_accel_bias = {0.1, 0.05, -0.08};
  const std::vector<SimImuRecord> imu = synthesizeImu(traj, opt);
  ASSERT_EQ(imu.size(), 2001u);

  // RK4 with step 2 dt: the middle sample is the midpoint measurement.
  NavState x{imu[0].truth.p_W_B, imu[0].truth.v_W, imu[0].truth.q_W_B};
  const double h = 2.0 * nsToSec(imu[1].sample.t_ns - imu[0].sample.t_ns);
  auto g = [&](size_t i) { return Eigen::Vector3d(imu[i].sample.gyro - imu[i].gyro_bias); };
  auto a = [&](size_t i) { return Eigen::Vector3d(imu[i].sample.accel - imu[i].accel_bias); };
  double max_p = 0, max_v = 0, max_r = 0;
  for (size_t i = 0; i + 2 < imu.size(); i += 2) {
    const NavState k1 = derivative(x, g(i), a(i));
    const NavState k2 = derivative(add(x, k1, h / 2), g(i + 1), a(i + 1));
    const NavState k3 = derivative(add(x, k2, h / 2), g(i + 1), a(i + 1));
    const NavState k4 = derivative(add(x, k3, h), g(i + 2), a(i + 2));
    x.p += h / 6 * (k1.p + 2 * k2.p + 2 * k3.p + k4.p);
    x.v += h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v);
    x.q.coeffs() += h / 6 * (k1.q.coeffs() + 2 * k2.q.coeffs() + 2 * k3.q.coeffs() + k4.q.coeffs());
    x.q.normalize();
    const SimBodyState& truth = imu[i + 2].truth;
    max_p = std::max(max_p, (x.p - truth.p_W_B).norm());
    max_v = std::max(max_v, (x.v - truth.v_W).norm());
    max_r = std::max(max_r, truth.q_W_B.angularDistance(x.q));
  }
  // 10 s of dead reckoning at 200 Hz: RK4 truncation only.
  EXPECT_LT(max_p, 1e-5) << "position drift";
  EXPECT_LT(max_v, 1e-5) << "velocity drift";
  EXPECT_LT(max_r, 1e-7) << "rotation drift";
}

TEST(SimImu, NoiseMatchesDensities) {
  const SineTrajectory traj = testTrajectory(100.0);
  SimImuOptions opt;
  opt.seed = 7;
  const std::vector<SimImuRecord> imu = synthesizeImu(traj, opt);
  const double dt = 1.0 / opt.rate_hz;
  double sg = 0, sa = 0, swg = 0, swa = 0;
  const size_t n = imu.size();
  for (size_t i = 0; i < n; ++i) {
    const ImuSample ideal = idealImu(imu[i].truth);
    sg += (imu[i].sample.gyro - ideal.gyro - imu[i].gyro_bias).squaredNorm();
    sa += (imu[i].sample.accel - ideal.accel - imu[i].accel_bias).squaredNorm();
    if (i + 1 < n) {
      swg += (imu[i + 1].gyro_bias - imu[i].gyro_bias).squaredNorm();
      swa += (imu[i + 1].accel_bias - imu[i].accel_bias).squaredNorm();
    }
  }
  const double m = 3.0 * n;
  EXPECT_NEAR(std::sqrt(sg / m), opt.gyro_noise_density / std::sqrt(dt),
              0.03 * opt.gyro_noise_density / std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(sa / m), opt.accel_noise_density / std::sqrt(dt),
              0.03 * opt.accel_noise_density / std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(swg / m), opt.gyro_random_walk * std::sqrt(dt),
              0.03 * opt.gyro_random_walk * std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(swa / m), opt.accel_random_walk * std::sqrt(dt),
              0.03 * opt.accel_random_walk * std::sqrt(dt));
}

TEST(SimImu, DeterministicInSeed) {
  const SineTrajectory traj = testTrajectory(2.0);
  SimImuOptions opt;
  opt.seed = 3;
  const auto a = synthesizeImu(traj, opt), b = synthesizeImu(traj, opt);
  opt.seed = 4;
  const auto c = synthesizeImu(traj, opt);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].sample.gyro, b[i].sample.gyro);
    EXPECT_EQ(a[i].sample.accel, b[i].sample.accel);
    differs = differs || a[i].sample.accel != c[i].sample.accel;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace adugs::data

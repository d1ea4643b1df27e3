// IMU preintegration against the analytic trajectory, finite differences and Monte-Carlo.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "data/sim/sim_imu.h"
#include "data/sim/sim_trajectory.h"
#include "vio/imu/imu_preintegration.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

constexpr int64_t kT0 = 1403715273262142976;  // EuRoC-size epoch: exercises time precision
constexpr int64_t kPeriodNs = 5'000'000;      // 200 Hz

data::SineTrajectory trajectory() {
  std::array<data::SineChannel, 6> ch;
  ch[data::SineTrajectory::kX] = {0.5, 0.0, {{1.5, 0.7, 0.1}, {0.3, 2.1, 1.0}}};
  ch[data::SineTrajectory::kY] = {-0.2, 0.0, {{1.2, 0.9, 1.3}, {0.2, 1.7, 0.4}}};
  ch[data::SineTrajectory::kZ] = {1.4, 0.0, {{0.25, 1.1, 0.2}}};
  ch[data::SineTrajectory::kYaw] = {0.3, 0.2, {{0.8, 0.5, 0.0}, {0.1, 2.3, 0.5}}};
  ch[data::SineTrajectory::kPitch] = {0.0, 0.0, {{0.15, 1.3, 0.3}}};
  ch[data::SineTrajectory::kRoll] = {0.05, 0.0, {{0.12, 1.9, 1.1}}};
  return data::SineTrajectory(kT0, kT0 + data::secToNs(5.0), ch);
}

// Ideal IMU (plus constant biases) at 200 Hz over [t0, t0 + duration].
std::vector<data::ImuSample> idealSamples(const data::SineTrajectory& traj, int64_t t0,
                                          double duration_s, const Eigen::Vector3d& ba,
                                          const Eigen::Vector3d& bg) {
  std::vector<data::ImuSample> out;
  for (int64_t t = t0; t <= t0 + data::secToNs(duration_s); t += kPeriodNs) {
    data::ImuSample s = data::idealImu(traj.stateAt(t));
    s.accel += ba;
    s.gyro += bg;
    out.push_back(s);
  }
  return out;
}

ImuPreintegration preintegrate(const std::vector<data::ImuSample>& samples,
                               const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) {
  ImuPreintegration pre(samples.front(), ba, bg);
  for (size_t k = 1; k < samples.size(); ++k) pre.integrate(samples[k]);
  return pre;
}

TEST(ImuPreintegration, DeltasMatchTrueRelativeMotion) {
  const data::SineTrajectory traj = trajectory();
  const Eigen::Vector3d ba(0.1, -0.05, 0.08), bg(0.01, -0.02, 0.015);
  const Eigen::Vector3d g = gravityWorld();
  for (double window : {0.5, 1.0}) {
    const int64_t ti = kT0 + data::secToNs(1.3);
    const ImuPreintegration pre = preintegrate(idealSamples(traj, ti, window, ba, bg), ba, bg);
    const data::SimBodyState si = traj.stateAt(ti), sj = traj.stateAt(pre.endNs());
    const double T = pre.sumDt();
    ASSERT_NEAR(T, window, 1e-12);
    const Eigen::Quaterniond qi_inv = si.q_W_B.conjugate();
    const Eigen::Vector3d dp = qi_inv * (sj.p_W_B - si.p_W_B - si.v_W * T - 0.5 * g * T * T);
    const Eigen::Vector3d dv = qi_inv * (sj.v_W - si.v_W - g * T);
    EXPECT_LT((pre.deltaP() - dp).norm(), 1e-4) << "window " << window;
    EXPECT_LT((pre.deltaV() - dv).norm(), 2e-4) << "window " << window;
    EXPECT_LT(pre.deltaQ().angularDistance(qi_inv * sj.q_W_B), 1e-6) << "window " << window;
  }
}

TEST(ImuPreintegration, ResidualIsZeroAtTruth) {
  const data::SineTrajectory traj = trajectory();
  const Eigen::Vector3d ba(0.1, -0.05, 0.08), bg(0.01, -0.02, 0.015);
  const int64_t ti = kT0 + data::secToNs(2.0);
  // Linearised at wrong biases, then evaluated at the true ones: first-order correction is enough.
  const Eigen::Vector3d ba_lin = ba + Eigen::Vector3d(0.01, 0.0, -0.01);
  const Eigen::Vector3d bg_lin = bg + Eigen::Vector3d(0.0, 1e-3, 0.0);
  const ImuPreintegration pre = preintegrate(idealSamples(traj, ti, 0.5, ba, bg), ba_lin, bg_lin);
  const data::SimBodyState si = traj.stateAt(ti), sj = traj.stateAt(pre.endNs());
  const Vector15d r =
      pre.evaluate(si.p_W_B, si.q_W_B, si.v_W, ba, bg, sj.p_W_B, sj.q_W_B, sj.v_W, ba, bg);
  EXPECT_LT(r.segment<3>(kStateP).norm(), 1e-4);
  EXPECT_LT(r.segment<3>(kStateQ).norm(), 1e-5);
  EXPECT_LT(r.segment<3>(kStateV).norm(), 2e-4);
  EXPECT_EQ(r.tail<6>().norm(), 0.0);
}

TEST(ImuPreintegration, RepropagateEqualsFreshIntegration) {
  const data::SineTrajectory traj = trajectory();
  const auto samples =
      idealSamples(traj, kT0, 0.3, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  ImuPreintegration a = preintegrate(samples, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d ba(0.2, 0.1, -0.1), bg(0.01, 0.02, -0.03);
  a.repropagate(ba, bg);
  const ImuPreintegration b = preintegrate(samples, ba, bg);
  EXPECT_EQ(a.deltaP(), b.deltaP());
  EXPECT_EQ(a.deltaQ().coeffs(), b.deltaQ().coeffs());
  EXPECT_EQ(a.covariance(), b.covariance());
  EXPECT_EQ(a.linearizedAccelBias(), ba);
  EXPECT_THROW(a.integrate(samples[3]), std::invalid_argument);
}

// The bias Jacobians are the exact derivatives of the discrete midpoint integration.
TEST(ImuPreintegration, BiasJacobiansMatchFiniteDifferences) {
  const data::SineTrajectory traj = trajectory();
  const Eigen::Vector3d ba(0.1, -0.05, 0.08), bg(0.01, -0.02, 0.015);
  const auto samples = idealSamples(traj, kT0 + data::secToNs(0.7), 1.0, ba, bg);
  const ImuPreintegration pre = preintegrate(samples, ba, bg);
  const double h = 1e-5;
  Eigen::Matrix3d dp_dba, dp_dbg, dv_dba, dv_dbg, dq_dbg;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    const ImuPreintegration ap = preintegrate(samples, ba + e, bg),
                            am = preintegrate(samples, ba - e, bg);
    const ImuPreintegration gp = preintegrate(samples, ba, bg + e),
                            gm = preintegrate(samples, ba, bg - e);
    dp_dba.col(k) = (ap.deltaP() - am.deltaP()) / (2 * h);
    dv_dba.col(k) = (ap.deltaV() - am.deltaV()) / (2 * h);
    dp_dbg.col(k) = (gp.deltaP() - gm.deltaP()) / (2 * h);
    dv_dbg.col(k) = (gp.deltaV() - gm.deltaV()) / (2 * h);
    dq_dbg.col(k) = (quaternionLog(pre.deltaQ().conjugate() * gp.deltaQ()) -
                     quaternionLog(pre.deltaQ().conjugate() * gm.deltaQ())) /
                    (2 * h);
    // The accelerometer bias does not move the rotation.
    EXPECT_LT(ap.deltaQ().angularDistance(am.deltaQ()), 1e-14);
  }
  auto rel = [](const Eigen::Matrix3d& a, const Eigen::Matrix3d& n) {
    return (a - n).norm() / n.norm();
  };
  EXPECT_LT(rel(pre.dpDba(), dp_dba), 1e-7);
  EXPECT_LT(rel(pre.dvDba(), dv_dba), 1e-7);
  EXPECT_LT(rel(pre.dpDbg(), dp_dbg), 1e-6);
  EXPECT_LT(rel(pre.dvDbg(), dv_dbg), 1e-6);
  EXPECT_LT(rel(pre.dqDbg(), dq_dbg), 1e-6);
  // First-order correction: a few mrad/s gyro-bias change is predicted up to second-order terms.
  const Eigen::Vector3d dbg(1e-3, -2e-3, 1e-3);
  const ImuPreintegration moved = preintegrate(samples, ba, bg + dbg);
  const ImuPreintegration::Deltas c = pre.correctedDeltas(ba, bg + dbg);
  EXPECT_LT((c.p - moved.deltaP()).norm(), 1e-5);
  EXPECT_LT(c.q.angularDistance(moved.deltaQ()), 1e-6);  // first-order effect: 2.4e-3 rad
}

// Residuals at the true states of noisy re-integrations (Kalibr noise, bias random walk) have the
// propagated covariance: block traces and the mean normalised error squared (NEES, ideally 15).
// 800 runs: the sample traces scatter by ~3%, so 12% is a 4-sigma bound (3000 runs: all
// within 1.5%).
TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const data::SineTrajectory traj = trajectory();
  data::SimImuOptions sim;
  sim.initial_accel_bias = {0.05, -0.02, 0.03};
  sim.initial_gyro_bias = {0.002, 0.001, -0.003};
  const data::SineTrajectory window(kT0, kT0 + data::secToNs(1.0), traj.channels());
  constexpr int kRuns = 800;
  std::vector<Vector15d> residuals;
  Matrix15d covariance = Matrix15d::Zero();
  for (int run = 0; run < kRuns; ++run) {
    sim.seed = 1000 + run;
    const std::vector<data::SimImuRecord> imu = data::synthesizeImu(window, sim);
    ImuPreintegration pre(imu.front().sample, imu.front().accel_bias, imu.front().gyro_bias);
    for (size_t k = 1; k < imu.size(); ++k) pre.integrate(imu[k].sample);
    if (run == 0) covariance = pre.covariance();
    const data::SimImuRecord &i = imu.front(), &j = imu.back();
    residuals.push_back(pre.evaluate(i.truth.p_W_B, i.truth.q_W_B, i.truth.v_W, i.accel_bias,
                                     i.gyro_bias, j.truth.p_W_B, j.truth.q_W_B, j.truth.v_W,
                                     j.accel_bias, j.gyro_bias));
  }
  Vector15d mean = Vector15d::Zero();
  for (const Vector15d& r : residuals) mean += r / kRuns;
  Matrix15d sample_cov = Matrix15d::Zero();
  for (const Vector15d& r : residuals)
    sample_cov += (r - mean) * (r - mean).transpose() / (kRuns - 1);
  for (int block = 0; block < 5; ++block) {
    const double model = covariance.block<3, 3>(3 * block, 3 * block).trace();
    const double mc = sample_cov.block<3, 3>(3 * block, 3 * block).trace();
    EXPECT_NEAR(mc / model, 1.0, 0.12) << "block " << block;
  }
  // Cross-correlation position-velocity (the dominant off-diagonal block).
  const double model_pv = covariance.block<3, 3>(kStateP, kStateV).trace();
  const double mc_pv = sample_cov.block<3, 3>(kStateP, kStateV).trace();
  EXPECT_NEAR(mc_pv / model_pv, 1.0, 0.15);
  const Matrix15d information = covariance.inverse();
  double nees = 0.0;
  for (const Vector15d& r : residuals) nees += (r - mean).dot(information * (r - mean)) / kRuns;
  EXPECT_NEAR(nees, 15.0, 1.5);
}

TEST(ImuPreintegration, InterpolateImuIsLinearInTime) {
  data::ImuSample a, b;
  a.t_ns = 100;
  b.t_ns = 300;
  a.gyro = {1, 2, 3};
  b.gyro = {3, 2, 1};
  b.accel = {4, 0, 0};
  const data::ImuSample m = interpolateImu(a, b, 150);
  EXPECT_EQ(m.t_ns, 150);
  EXPECT_TRUE(m.gyro.isApprox(Eigen::Vector3d(1.5, 2, 2.5)));
  EXPECT_TRUE(m.accel.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_THROW(interpolateImu(a, b, 301), std::invalid_argument);
}

TEST(ImuPreintegration, ReadingAtATimeInterpolatesInsideAndHoldsOutsideTheBuffer) {
  std::deque<data::ImuSample> samples(3);
  for (int k = 0; k < 3; ++k) {
    samples[k].t_ns = 100 * (k + 1);  // 100, 200, 300
    samples[k].gyro = Eigen::Vector3d::Constant(k);
    samples[k].accel = Eigen::Vector3d(10.0 * k, 0, 0);
  }
  const data::ImuSample between = imuReadingAt(samples, 225);
  EXPECT_EQ(between.t_ns, 225);
  EXPECT_TRUE(between.gyro.isApprox(Eigen::Vector3d::Constant(1.25)));
  EXPECT_TRUE(between.accel.isApprox(Eigen::Vector3d(12.5, 0, 0)));
  EXPECT_EQ(imuReadingAt(samples, 200).gyro, Eigen::Vector3d::Constant(1));  // on a sample
  const data::ImuSample before = imuReadingAt(samples, 40), after = imuReadingAt(samples, 370);
  EXPECT_EQ(before.t_ns, 40);
  EXPECT_EQ(before.gyro, Eigen::Vector3d::Constant(0));  // the first held
  EXPECT_EQ(after.t_ns, 370);
  EXPECT_EQ(after.accel, Eigen::Vector3d(20, 0, 0));  // the last held
  EXPECT_THROW(imuReadingAt({}, 100), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio

namespace adugs::vio {
namespace {

// One 50 ms step with the same sample at both ends (a frame right after an IMU hole, the held
// sample): delta p and delta v share one noise and the raw covariance is singular; the square-root
// information must still exist, be finite, and reproduce the variances it can.
TEST(ImuPreintegration, SingleStepAfterAnImuHoleStillHasAnInformation) {
  data::ImuSample a;
  a.t_ns = 0;
  a.accel = Eigen::Vector3d(0.3, -0.1, 9.81);
  a.gyro = Eigen::Vector3d(0.1, 0.0, -0.2);
  data::ImuSample b = a;
  b.t_ns = 50'000'000;
  ImuPreintegration pre(a, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  pre.integrate(b);
  Matrix15d L;
  ASSERT_NO_THROW(L = pre.sqrtInformation());
  ASSERT_TRUE(L.allFinite());
  // The rotation block has its own noise: its variance comes back through L.
  const Matrix15d cov = (L.transpose() * L).inverse();
  for (int i = 3; i < 6; ++i)
    EXPECT_NEAR(cov(i, i), pre.covariance()(i, i), 1e-3 * pre.covariance()(i, i));
}

}  // namespace
}  // namespace adugs::vio

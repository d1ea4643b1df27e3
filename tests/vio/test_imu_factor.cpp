// ImuFactor: whitened residual at truth, analytic vs numeric Jacobians away from truth, and a
// Ceres solve that recovers the end state from the start state and the IMU alone.
#include "vio/estimator/imu_factor.h"

#include <array>
#include <memory>
#include <random>

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include "data/sim/sim_imu.h"
#include "data/sim/sim_trajectory.h"
#include "tests/vio/jacobian_check.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

constexpr int64_t kEurocEpochNs = 1403715273262142976;

struct Scenario {
  std::shared_ptr<ImuPreintegration> pre;
  std::array<double, 7> pose_i, pose_j;
  std::array<double, 9> sb_i, sb_j;  // v, ba, bg
};

// 0.5 s of ideal IMU (200 Hz, constant biases) along a sine trajectory, and the true states.
Scenario makeScenario() {
  std::array<data::SineChannel, 6> ch;
  ch[data::SineTrajectory::kX] = {0.5, 0.0, {{1.5, 0.7, 0.1}, {0.3, 2.1, 1.0}}};
  ch[data::SineTrajectory::kY] = {-0.2, 0.0, {{1.2, 0.9, 1.3}}};
  ch[data::SineTrajectory::kZ] = {1.4, 0.0, {{0.25, 1.1, 0.2}}};
  ch[data::SineTrajectory::kYaw] = {0.3, 0.2, {{0.8, 0.5, 0.0}}};
  ch[data::SineTrajectory::kPitch] = {0.0, 0.0, {{0.15, 1.3, 0.3}}};
  ch[data::SineTrajectory::kRoll] = {0.05, 0.0, {{0.12, 1.9, 1.1}}};
  const data::SineTrajectory traj(kEurocEpochNs, kEurocEpochNs + data::secToNs(2.0), ch);
  const Eigen::Vector3d ba(0.1, -0.05, 0.08), bg(0.01, -0.02, 0.015);
  const int64_t ti = kEurocEpochNs + data::secToNs(0.4), tj = ti + data::secToNs(0.5);
  Scenario s;
  for (int64_t t = ti; t <= tj; t += 5'000'000) {
    data::ImuSample m = data::idealImu(traj.stateAt(t));
    m.accel += ba;
    m.gyro += bg;
    if (!s.pre) s.pre = std::make_shared<ImuPreintegration>(m, ba, bg);
    else s.pre->integrate(m);
  }
  auto fill = [&](int64_t t, std::array<double, 7>& pose, std::array<double, 9>& sb) {
    const data::SimBodyState st = traj.stateAt(t);
    setPose(st.p_W_B, st.q_W_B, pose.data());
    Eigen::Map<Eigen::Matrix<double, 9, 1>> v(sb.data());
    v << st.v_W, ba, bg;
  };
  fill(ti, s.pose_i, s.sb_i);
  fill(tj, s.pose_j, s.sb_j);
  return s;
}

void perturbPose(std::mt19937& rng, double dp, double dtheta, std::array<double, 7>& pose) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> d;
  for (int k = 0; k < 6; ++k) d(k) = n(rng) * (k < 3 ? dp : dtheta);
  std::array<double, 7> out;
  PoseManifold().Plus(pose.data(), d.data(), out.data());
  pose = out;
}

void perturbSpeedBias(std::mt19937& rng, std::array<double, 9>& sb) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 9; ++k) sb[k] += n(rng) * (k < 3 ? 0.2 : k < 6 ? 0.05 : 0.01);
}

TEST(ImuFactor, WhitenedResidualIsSmallAtTruth) {
  Scenario s = makeScenario();
  const ImuFactor factor(s.pre);
  const double* params[] = {s.pose_i.data(), s.sb_i.data(), s.pose_j.data(), s.sb_j.data()};
  Vector15d r;
  ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
  // Only the midpoint discretisation error (~1e-5 m) remains, far below one sigma.
  EXPECT_LT(r.norm(), 0.1);
}

TEST(ImuFactor, AnalyticJacobiansMatchNumericAwayFromTruth) {
  const Scenario truth = makeScenario();
  const PoseManifold pose_manifold;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    Scenario s = truth;
    perturbPose(rng, 0.3, 0.2, s.pose_i);
    perturbPose(rng, 0.3, 0.2, s.pose_j);
    perturbSpeedBias(rng, s.sb_i);
    perturbSpeedBias(rng, s.sb_j);
    const ImuFactor factor(s.pre);
    const auto result = testing::checkJacobians(
        factor, {s.pose_i.data(), s.sb_i.data(), s.pose_j.data(), s.sb_j.data()},
        {&pose_manifold, nullptr, &pose_manifold, nullptr}, 1e-5, 1e-6);
    EXPECT_TRUE(result.ok) << "trial " << trial << "\n" << result.report;
  }
}

TEST(ImuFactor, SolveRecoversEndStateFromStartState) {
  const Scenario truth = makeScenario();
  Scenario s = truth;
  std::mt19937 rng(3);
  perturbPose(rng, 0.2, 0.1, s.pose_j);
  for (int k = 0; k < 3; ++k) s.sb_j[k] += 0.3;
  ceres::Problem problem;
  problem.AddResidualBlock(new ImuFactor(s.pre), nullptr, s.pose_i.data(), s.sb_i.data(),
                           s.pose_j.data(), s.sb_j.data());
  problem.SetManifold(s.pose_i.data(), new PoseManifold);
  problem.SetManifold(s.pose_j.data(), new PoseManifold);
  problem.SetParameterBlockConstant(s.pose_i.data());
  problem.SetParameterBlockConstant(s.sb_i.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  const Eigen::Vector3d dp = posePosition(s.pose_j.data()) - posePosition(truth.pose_j.data());
  EXPECT_LT(dp.norm(), 1e-4);
  EXPECT_LT(Eigen::Quaterniond(poseRotation(s.pose_j.data()))
                .angularDistance(Eigen::Quaterniond(poseRotation(truth.pose_j.data()))),
            1e-6);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(s.sb_j[k], truth.sb_j[k], 2e-4) << k;
}

}  // namespace
}  // namespace adugs::vio

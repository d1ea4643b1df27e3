// Back-end building blocks: preintegration, factor evaluation, a 10-keyframe visual-inertial
// window solve (the per-keyframe optimisation; product bar <= 25 ms) and a marginalisation.
// Run: build-*/tests/bench/bench_vio_factors --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
// ADUGS_BENCH_VERBOSE=1 prints Ceres' full report of every window solve.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "data/sim/sim_imu.h"
#include "data/sim/sim_scene.h"
#include "data/sim/sim_trajectory.h"
#include "vio/estimator/imu_factor.h"
#include "vio/estimator/marginalization.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/estimator/reprojection_factor.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

constexpr int64_t kT0 = 1'000'000'000;
constexpr double kFocal = 460.0;

data::SineTrajectory benchTrajectory() {
  std::array<data::SineChannel, 6> ch;
  ch[data::SineTrajectory::kX] = {0.0, 0.8, {{0.4, 0.9, 0.1}}};
  ch[data::SineTrajectory::kY] = {0.0, 0.0, {{0.5, 0.7, 1.3}}};
  ch[data::SineTrajectory::kZ] = {1.4, 0.0, {{0.15, 1.1, 0.2}}};
  ch[data::SineTrajectory::kYaw] = {0.0, 0.0, {{0.3, 0.5, 0.0}}};
  ch[data::SineTrajectory::kPitch] = {0.0, 0.0, {{0.08, 1.3, 0.3}}};
  ch[data::SineTrajectory::kRoll] = {0.0, 0.0, {{0.06, 1.9, 1.1}}};
  return data::SineTrajectory(kT0, kT0 + data::secToNs(4.0), ch);
}

using Pose = std::array<double, 7>;
using SpeedBias = std::array<double, 9>;

struct Observation {
  int frame;
  Eigen::Vector2d pt;
};
struct Feature {
  int host;
  std::vector<Observation> obs;  // obs[0] is the host observation
  double lambda_true;
};

// A sliding window of keyframes along the trajectory, noisy IMU between them and features with
// 0.5 px noise, plus the truth and a perturbed initial guess.
struct Window {
  int n_frames = 10;
  std::vector<Pose> pose_true, pose_init;
  std::vector<SpeedBias> sb_true, sb_init;
  Pose T_B_C;
  std::vector<std::shared_ptr<ImuPreintegration>> imu;  // imu[k]: frame k -> k + 1
  std::vector<Feature> features;
  std::vector<double> lambda_init;

  Window() {
    const data::SineTrajectory traj = benchTrajectory();
    data::SimImuOptions sim;
    sim.seed = 3;
    const std::vector<data::SimImuRecord> imu_records = data::synthesizeImu(traj, sim);
    const Eigen::Isometry3d T_B_C_iso = data::defaultSimT_B_C();
    setPose(T_B_C_iso.translation(), Eigen::Quaterniond(T_B_C_iso.linear()), T_B_C.data());
    constexpr int kSamplesPerFrame = 20;  // keyframes every 0.1 s at 200 Hz
    std::vector<Eigen::Isometry3d> T_W_C(n_frames);
    for (int f = 0; f < n_frames; ++f) {
      const data::SimImuRecord& rec = imu_records[f * kSamplesPerFrame];
      Pose p;
      setPose(rec.truth.p_W_B, rec.truth.q_W_B, p.data());
      pose_true.push_back(p);
      SpeedBias sb;
      Eigen::Map<Eigen::Matrix<double, 9, 1>>(sb.data()) << rec.truth.v_W, rec.accel_bias, rec.gyro_bias;
      sb_true.push_back(sb);
      Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
      T_W_B.linear() = rec.truth.q_W_B.toRotationMatrix();
      T_W_B.translation() = rec.truth.p_W_B;
      T_W_C[f] = T_W_B * T_B_C_iso;
      if (f + 1 < n_frames) {
        auto pre = std::make_shared<ImuPreintegration>(rec.sample, Eigen::Vector3d::Zero(),
                                                       Eigen::Vector3d::Zero());
        for (int k = 1; k <= kSamplesPerFrame; ++k)
          pre->integrate(imu_records[f * kSamplesPerFrame + k].sample);
        imu.push_back(pre);
      }
    }
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.5, 0.5), depth(2.0, 12.0);
    std::normal_distribution<double> px_noise(0.0, 0.5 / kFocal), n(0.0, 1.0);
    while (features.size() < 150) {
      Feature ft;
      ft.host = static_cast<int>(features.size() % (n_frames - 2));
      const double d = depth(rng);
      const Eigen::Vector2d pt(u(rng), 0.7 * u(rng));
      const Eigen::Vector3d p_W = T_W_C[ft.host] * (d * Eigen::Vector3d(pt.x(), pt.y(), 1.0));
      ft.lambda_true = 1.0 / d;
      for (int f = ft.host; f < n_frames; ++f) {
        const Eigen::Vector3d p_C = T_W_C[f].inverse() * p_W;
        if (p_C.z() < 0.5) continue;
        const Eigen::Vector2d obs = p_C.head<2>() / p_C.z();
        if (std::abs(obs.x()) > 0.6 || std::abs(obs.y()) > 0.45) continue;
        ft.obs.push_back({f, obs + Eigen::Vector2d(px_noise(rng), px_noise(rng))});
      }
      if (ft.obs.size() >= 3 && ft.obs[0].frame == ft.host) {
        features.push_back(ft);
        lambda_init.push_back(ft.lambda_true * (1.0 + 0.2 * u(rng)));
      }
    }
    for (int f = 0; f < n_frames; ++f) {
      Pose p = pose_true[f];
      if (f > 0) {
        Eigen::Matrix<double, 6, 1> d;
        for (int k = 0; k < 6; ++k) d(k) = n(rng) * (k < 3 ? 0.05 : 0.01);
        PoseManifold().Plus(pose_true[f].data(), d.data(), p.data());
      }
      pose_init.push_back(p);
      SpeedBias sb = sb_true[f];
      for (int k = 0; k < 3; ++k) sb[k] += 0.05 * n(rng);
      for (int k = 3; k < 9; ++k) sb[k] = 0.0;  // biases unknown
      sb_init.push_back(sb);
    }
  }

  int numObservations() const {
    int n = 0;
    for (const Feature& f : features) n += static_cast<int>(f.obs.size()) - 1;
    return n;
  }
};

const Window& window() {
  static const Window w;
  return w;
}

// Problem with the window's factors on the given state; the first pose is the gauge.
struct WindowProblem {
  std::vector<Pose> pose;
  std::vector<SpeedBias> sb;
  Pose T_B_C;
  std::vector<double> lambda;
  PoseManifold manifold;
  ceres::CauchyLoss loss{1.0};
  std::unique_ptr<ceres::Problem> problem;

  explicit WindowProblem(const Window& w)
      : pose(w.pose_init), sb(w.sb_init), T_B_C(w.T_B_C), lambda(w.lambda_init) {
    ceres::Problem::Options o;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(o);
    for (Pose& p : pose) problem->AddParameterBlock(p.data(), 7, &manifold);
    problem->AddParameterBlock(T_B_C.data(), 7, &manifold);
    problem->SetParameterBlockConstant(T_B_C.data());
    problem->SetParameterBlockConstant(pose[0].data());
    for (size_t k = 0; k < w.imu.size(); ++k)
      problem->AddResidualBlock(new ImuFactor(w.imu[k]), nullptr, pose[k].data(), sb[k].data(),
                                pose[k + 1].data(), sb[k + 1].data());
    const double s = reprojectionSqrtInformation(kFocal);
    for (size_t i = 0; i < w.features.size(); ++i) {
      const Feature& f = w.features[i];
      for (size_t o = 1; o < f.obs.size(); ++o)
        problem->AddResidualBlock(new ReprojectionFactor(f.obs[0].pt, f.obs[o].pt, s), &loss,
                                  pose[f.host].data(), pose[f.obs[o].frame].data(), T_B_C.data(),
                                  &lambda[i]);
    }
  }
};

ceres::Solver::Options windowSolverOptions(
    ceres::LinearSolverType linear_solver = ceres::DENSE_SCHUR) {
  ceres::Solver::Options o;  // as VINS-Mono: dogleg, dense Schur, 8 iterations
  o.linear_solver_type = linear_solver;
  o.trust_region_strategy_type = ceres::DOGLEG;
  o.max_num_iterations = 8;
  o.num_threads = 1;
  return o;
}

void BM_PreintegrateTenSamplesAndRepropagate(benchmark::State& state) {
  const auto& samples = window().imu[0]->samples();
  for (auto _ : state) {
    ImuPreintegration pre(samples[0], Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    for (int k = 1; k <= 10; ++k) pre.integrate(samples[k]);
    pre.repropagate(Eigen::Vector3d(0.01, 0.0, 0.0), Eigen::Vector3d(0.0, 1e-3, 0.0));
    benchmark::DoNotOptimize(pre.deltaP());
  }
}
BENCHMARK(BM_PreintegrateTenSamplesAndRepropagate);

void BM_ImuFactorEvaluateWithJacobians(benchmark::State& state) {
  const Window& w = window();
  const ImuFactor factor(w.imu[0]);
  const double* params[] = {w.pose_init[0].data(), w.sb_init[0].data(), w.pose_init[1].data(),
                            w.sb_init[1].data()};
  std::array<double, 15> r;
  std::array<double, 15 * 7> j0, j2;
  std::array<double, 15 * 9> j1, j3;
  double* jac[] = {j0.data(), j1.data(), j2.data(), j3.data()};
  for (auto _ : state) {
    factor.Evaluate(params, r.data(), jac);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(j3);
  }
}
BENCHMARK(BM_ImuFactorEvaluateWithJacobians);

void BM_ReprojectionFactorEvaluateWithJacobians(benchmark::State& state) {
  const Window& w = window();
  const Feature& f = w.features[0];
  const ReprojectionFactor factor(f.obs[0].pt, f.obs[1].pt, reprojectionSqrtInformation(kFocal));
  const double* params[] = {w.pose_init[f.host].data(), w.pose_init[f.obs[1].frame].data(),
                            w.T_B_C.data(), &w.lambda_init[0]};
  std::array<double, 2> r;
  std::array<double, 14> j0, j1, j2;
  std::array<double, 2> j3;
  double* jac[] = {j0.data(), j1.data(), j2.data(), j3.data()};
  for (auto _ : state) {
    factor.Evaluate(params, r.data(), jac);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(j3);
  }
}
BENCHMARK(BM_ReprojectionFactorEvaluateWithJacobians);

// One keyframe optimisation: build the problem and solve it (8 iterations max), single thread.
void BM_WindowSolve10Keyframes150Features(benchmark::State& state) {
  const Window& w = window();
  double final_cost = 0.0;
  for (auto _ : state) {
    WindowProblem wp(w);
    ceres::Solver::Summary summary;
    ceres::Solve(windowSolverOptions(static_cast<ceres::LinearSolverType>(state.range(0))),
                 wp.problem.get(), &summary);
    final_cost = summary.final_cost;
    if (std::getenv("ADUGS_BENCH_VERBOSE")) std::fprintf(stderr, "%s\n", summary.FullReport().c_str());
  }
  state.counters["observations"] = w.numObservations();
  state.counters["final_cost"] = final_cost;
}
BENCHMARK(BM_WindowSolve10Keyframes150Features)
    ->Unit(benchmark::kMillisecond)
    ->ArgName("linear_solver")  // ceres::LinearSolverType
    ->Arg(ceres::DENSE_SCHUR)
    ->Arg(ceres::SPARSE_SCHUR)
    ->Arg(ceres::SPARSE_NORMAL_CHOLESKY);  // DENSE_NORMAL_CHOLESKY: ~10x slower, left out

// Marginalising the oldest keyframe (pose, speed-bias and the features it hosts) after a solve.
void BM_MarginalizeOldestKeyframe(benchmark::State& state) {
  const Window& w = window();
  WindowProblem wp(w);
  ceres::Solver::Summary summary;
  ceres::Solve(windowSolverOptions(), wp.problem.get(), &summary);
  const double s = reprojectionSqrtInformation(kFocal);
  const ImuFactor imu_factor(w.imu[0]);
  std::vector<std::unique_ptr<ReprojectionFactor>> reprojections;
  std::vector<std::array<int, 2>> reprojection_index;  // feature, observation
  for (size_t i = 0; i < w.features.size(); ++i) {
    const Feature& f = w.features[i];
    if (f.host != 0) continue;
    for (size_t o = 1; o < f.obs.size(); ++o) {
      reprojections.push_back(std::make_unique<ReprojectionFactor>(f.obs[0].pt, f.obs[o].pt, s));
      reprojection_index.push_back({static_cast<int>(i), static_cast<int>(o)});
    }
  }
  size_t kept_size = 0;
  for (auto _ : state) {
    Marginalizer m;
    for (Pose& p : wp.pose) m.setManifold(p.data(), &wp.manifold);
    m.setManifold(wp.T_B_C.data(), &wp.manifold);
    m.addResidualBlock(&imu_factor, nullptr,
                       {wp.pose[0].data(), wp.sb[0].data(), wp.pose[1].data(), wp.sb[1].data()});
    std::vector<const double*> marginalized = {wp.pose[0].data(), wp.sb[0].data()};
    for (size_t k = 0; k < reprojections.size(); ++k) {
      const auto [i, o] = reprojection_index[k];
      const Feature& f = w.features[i];
      m.addResidualBlock(reprojections[k].get(), &wp.loss,
                         {wp.pose[0].data(), wp.pose[f.obs[o].frame].data(), wp.T_B_C.data(),
                          &wp.lambda[i]});
      if (o == 1) marginalized.push_back(&wp.lambda[i]);
    }
    const auto prior = m.marginalize(marginalized);
    kept_size = static_cast<size_t>(prior->tangentSize());
    benchmark::DoNotOptimize(prior);
  }
  state.counters["marginalized_features"] = static_cast<double>(reprojection_index.empty() ? 0 : reprojection_index.size());
  state.counters["kept_tangent"] = static_cast<double>(kept_size);
}
BENCHMARK(BM_MarginalizeOldestKeyframe)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace adugs::vio

BENCHMARK_MAIN();

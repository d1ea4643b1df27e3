// Inverse-depth reprojection factors: zero at truth, analytic vs numeric Jacobians (pose_i,
// pose_j, extrinsic, inverse depth, time offset), and a small inverse-depth solve.
#include "vio/estimator/reprojection_factor.h"
#include "vio/estimator/reprojection_factor_pool.h"

#include <array>
#include <random>
#include <vector>

#include <ceres/problem.h>
#include <ceres/sized_cost_function.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include "data/sim/sim_scene.h"
#include "tests/vio/jacobian_check.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

using Pose = std::array<double, 7>;
constexpr double kSqrtInfo = 460.0 / 1.5;  // EuRoC-like focal length

struct Rig {
  Pose pose_i, pose_j, T_B_C;
};

// Body moving forward (body x) and sideways, camera looking along body x.
Rig makeRig() {
  Rig s;
  setPose(Eigen::Vector3d(1.0, 2.0, 1.5), quaternionExp(Eigen::Vector3d(0.05, -0.02, 0.6)),
          s.pose_i.data());
  setPose(Eigen::Vector3d(1.3, 2.5, 1.45), quaternionExp(Eigen::Vector3d(0.02, 0.03, 0.75)),
          s.pose_j.data());
  const Eigen::Isometry3d T = data::defaultSimT_B_C();
  setPose(T.translation(), Eigen::Quaterniond(T.linear()), s.T_B_C.data());
  return s;
}

Eigen::Isometry3d toIsometry(const Pose& x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(poseRotation(x.data())).toRotationMatrix();
  T.translation() = posePosition(x.data());
  return T;
}

// A feature: normalised coordinates in i and j and its true inverse depth.
struct Feature {
  Eigen::Vector2d pt_i, pt_j;
  double lambda;
};

Feature makeFeature(const Rig& s, const Eigen::Vector2d& pt_i, double depth) {
  const Eigen::Vector3d p_ci = depth * Eigen::Vector3d(pt_i.x(), pt_i.y(), 1.0);
  const Eigen::Isometry3d T_B_C = toIsometry(s.T_B_C);
  const Eigen::Vector3d p_w = toIsometry(s.pose_i) * (T_B_C * p_ci);
  const Eigen::Vector3d p_cj = (toIsometry(s.pose_j) * T_B_C).inverse() * p_w;
  return {pt_i, p_cj.head<2>() / p_cj.z(), 1.0 / depth};
}

void perturb(std::mt19937& rng, double dp, double dtheta, Pose& x) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> d;
  for (int k = 0; k < 6; ++k) d(k) = n(rng) * (k < 3 ? dp : dtheta);
  Pose out;
  PoseManifold().Plus(x.data(), d.data(), out.data());
  x = out;
}

TEST(ReprojectionFactor, ZeroResidualAtTruth) {
  const Rig s = makeRig();
  const Feature f = makeFeature(s, {0.1, -0.05}, 4.0);
  ASSERT_GT(f.lambda, 0.0);
  const ReprojectionFactor factor(f.pt_i, f.pt_j, kSqrtInfo);
  const double* params[] = {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &f.lambda};
  Eigen::Vector2d r;
  ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-10);

  // With the time offset: observations recorded with td_i / td_j and the same current td.
  const ReprojectionTdFactor td_factor(f.pt_i, f.pt_j, {0.3, -0.1}, {0.2, 0.4}, 0.004, 0.004,
                                       kSqrtInfo);
  const double td = 0.004;
  const double* td_params[] = {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &f.lambda, &td};
  ASSERT_TRUE(td_factor.Evaluate(td_params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-10);
}

TEST(ReprojectionFactor, AnalyticJacobiansMatchNumeric) {
  const PoseManifold pm;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int trial = 0; trial < 5; ++trial) {
    Rig s = makeRig();
    const Feature f = makeFeature(s, {u(rng), u(rng)}, 2.0 + 6.0 * (u(rng) + 0.3));
    perturb(rng, 0.05, 0.02, s.pose_i);
    perturb(rng, 0.05, 0.02, s.pose_j);
    perturb(rng, 0.01, 0.01, s.T_B_C);
    double lambda = f.lambda * 1.2;
    const ReprojectionFactor factor(f.pt_i, f.pt_j, kSqrtInfo);
    const auto plain = testing::checkJacobians(
        factor, {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambda}, {&pm, &pm, &pm, nullptr});
    EXPECT_TRUE(plain.ok) << "trial " << trial << "\n" << plain.report;

    double td = 0.01;
    const ReprojectionTdFactor td_factor(f.pt_i, f.pt_j, {0.3, -0.1}, {0.2, 0.4}, 0.002, -0.003,
                                         kSqrtInfo);
    const auto with_td = testing::checkJacobians(
        td_factor, {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambda, &td},
        {&pm, &pm, &pm, nullptr, nullptr});
    EXPECT_TRUE(with_td.ok) << "trial " << trial << "\n" << with_td.report;
  }
}

// The checker itself must catch a Jacobian that is 0.1% off.
class SkewedFactor : public ceres::SizedCostFunction<2, 7, 7, 7, 1> {
 public:
  explicit SkewedFactor(const ReprojectionFactor& inner) : inner_(inner) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    inner_.Evaluate(p, r, J);
    if (J && J[3]) J[3][0] *= 1.001;
    return true;
  }

 private:
  const ReprojectionFactor& inner_;
};

// Skews the tangent Jacobian of pose_i (the one the window solver uses).
class SkewedTangentFactor : public TangentCostFunction {
 public:
  explicit SkewedTangentFactor(const ReprojectionFactor& inner)
      : TangentCostFunction(2, {kPoseSize, kPoseSize, kPoseSize, 1}), inner_(inner) {}
  bool EvaluateTangent(double const* const* p, double* r, double** J) const override {
    inner_.EvaluateTangent(p, r, J);
    if (J && J[0]) J[0][4] *= 1.001;
    return true;
  }

 private:
  const ReprojectionFactor& inner_;
};

TEST(ReprojectionFactor, JacobianCheckerCatchesWrongJacobian) {
  const PoseManifold pm;
  Rig s = makeRig();
  const Feature f = makeFeature(s, {0.1, 0.2}, 3.0);
  double lambda = f.lambda;
  const ReprojectionFactor good(f.pt_i, f.pt_j, kSqrtInfo);
  const SkewedFactor bad(good);
  const auto result = testing::checkJacobians(
      bad, {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambda}, {&pm, &pm, &pm, nullptr});
  EXPECT_FALSE(result.ok);
  const SkewedTangentFactor bad_tangent(good);
  const auto tangent_result = testing::checkJacobians(
      bad_tangent, {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambda},
      {&pm, &pm, &pm, nullptr});
  EXPECT_FALSE(tangent_result.ok);
  EXPECT_TRUE(testing::checkJacobians(good, {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambda},
                                      {&pm, &pm, &pm, nullptr})
                  .ok);
}

TEST(ReprojectionFactor, SolveRecoversInverseDepthsWithPosesFixed) {
  Rig s = makeRig();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.4, 0.4), depth(1.5, 10.0), scale(0.6, 1.5);
  std::vector<Feature> features;
  std::vector<double> lambdas;
  for (int k = 0; k < 50; ++k) {
    features.push_back(makeFeature(s, {u(rng), u(rng)}, depth(rng)));
    lambdas.push_back(features.back().lambda * scale(rng));  // up to 50% off
  }
  ceres::Problem problem;
  for (size_t k = 0; k < features.size(); ++k) {
    problem.AddResidualBlock(new ReprojectionFactor(features[k].pt_i, features[k].pt_j, kSqrtInfo),
                             nullptr, s.pose_i.data(), s.pose_j.data(), s.T_B_C.data(), &lambdas[k]);
  }
  for (double* block : {s.pose_i.data(), s.pose_j.data(), s.T_B_C.data()}) {
    problem.SetManifold(block, new PoseManifold);
    problem.SetParameterBlockConstant(block);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  for (size_t k = 0; k < features.size(); ++k)
    EXPECT_NEAR(lambdas[k], features[k].lambda, 1e-6 * features[k].lambda) << k;
}

// A factor the pool hands out again carries only the new observation, with and without the time
// offset: zero residual at the new observation's truth (a field left from the factor's previous
// use would move it), and residual and Jacobians equal to a newly made factor's.
TEST(ReprojectionFactorPool, AReusedFactorEvaluatesAsANewOne) {
  const Rig s = makeRig();
  const Feature first = makeFeature(s, {0.1, -0.05}, 4.0), second = makeFeature(s, {-0.2, 0.15}, 7.0);
  double lambda = second.lambda, td = 0.004;  // the second observation's truth
  double* params[] = {const_cast<double*>(s.pose_i.data()), const_cast<double*>(s.pose_j.data()),
                      const_cast<double*>(s.T_B_C.data()), &lambda, &td};
  auto evaluate = [&](const ceres::CostFunction& f) {
    const size_t n = f.parameter_block_sizes().size();
    std::vector<double> out(2);
    std::vector<std::vector<double>> J(n);
    std::vector<double*> J_ptrs;
    for (size_t k = 0; k < n; ++k) {
      J[k].resize(static_cast<size_t>(2 * f.parameter_block_sizes()[k]));
      J_ptrs.push_back(J[k].data());
    }
    EXPECT_TRUE(f.Evaluate(params, out.data(), J_ptrs.data()));
    for (const auto& j : J) out.insert(out.end(), j.begin(), j.end());
    return out;
  };

  ReprojectionFactorPool pool;
  const ReprojectionFactor* a = pool.plain(first.pt_i, first.pt_j, kSqrtInfo);
  const ReprojectionTdFactor* a_td =
      pool.withTimeOffset(first.pt_i, first.pt_j, {0.3, -0.1}, {0.2, 0.4}, 0.002, -0.003, kSqrtInfo);
  EXPECT_NE(pool.plain(first.pt_i, first.pt_j, kSqrtInfo), a);  // still in use: a second factor
  pool.reuseAll();
  const ReprojectionFactor* b = pool.plain(second.pt_i, second.pt_j, 2.0 * kSqrtInfo);
  const ReprojectionTdFactor* b_td = pool.withTimeOffset(second.pt_i, second.pt_j, {-0.1, 0.2},
                                                         {0.5, -0.3}, 0.004, 0.004, 2.0 * kSqrtInfo);
  EXPECT_EQ(b, a);  // the same objects, reused
  EXPECT_EQ(b_td, a_td);
  for (const ceres::CostFunction* f : {static_cast<const ceres::CostFunction*>(b),
                                       static_cast<const ceres::CostFunction*>(b_td)}) {
    Eigen::Vector2d r;
    ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-9);
  }
  lambda *= 1.2, td = 0.01;  // away from truth: the Jacobians and residual of a new factor
  EXPECT_EQ(evaluate(*b), evaluate(ReprojectionFactor(second.pt_i, second.pt_j, 2.0 * kSqrtInfo)));
  EXPECT_EQ(evaluate(*b_td), evaluate(ReprojectionTdFactor(second.pt_i, second.pt_j, {-0.1, 0.2},
                                                           {0.5, -0.3}, 0.004, 0.004,
                                                           2.0 * kSqrtInfo)));
}

}  // namespace
}  // namespace adugs::vio

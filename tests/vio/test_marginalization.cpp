// Marginalisation: exact on a linear problem, analytic prior-factor Jacobians, and a pose chain
// whose reduced problem keeps the full problem's estimate.
#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <random>
#include <vector>

#include "tests/vio/jacobian_check.h"
#include "vio/estimator/marginalization.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {
namespace {

// r = sum_k A_k x_k - b over Euclidean blocks.
class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd b)
      : A_(std::move(A)), b_(std::move(b)) {
    set_num_residuals(static_cast<int>(b_.size()));
    for (const auto& a : A_) mutable_parameter_block_sizes()->push_back(static_cast<int>(a.cols()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, b_.size());
    r = -b_;
    for (size_t k = 0; k < A_.size(); ++k) {
      r += A_[k] * Eigen::Map<const Eigen::VectorXd>(x[k], A_[k].cols());
      if (jacobians && jacobians[k]) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[k], A_[k].rows(), A_[k].cols()) = A_[k];
      }
    }
    return true;
  }

 private:
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd b_;
};

// Entries drawn from N(0, 1).
Eigen::MatrixXd randomMatrix(int rows, int cols, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < m.size(); ++i) m.data()[i] = n(rng);
  return m;
}

ceres::Solver::Options tightOptions() {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-16;
  o.max_num_iterations = 100;
  return o;
}

TEST(Marginalization, LinearProblemReducedSolutionEqualsFullSolution) {
  std::mt19937 rng(1);
  auto random = [&](int rows, int cols) { return randomMatrix(rows, cols, rng); };
  // Blocks x1 (2, marginalised), x2 (3), x3 (2); residuals on {x1}, {x1, x2}, {x1, x3}, {x2, x3}.
  std::array<double, 2> x1{0.5, -1.0};
  std::array<double, 3> x2{0.0, 0.0, 0.0};
  std::array<double, 2> x3{0.0, 0.0};
  LinearCost c1({random(3, 2)}, random(3, 1));
  LinearCost c12({random(3, 2), random(3, 3)}, random(3, 1));
  LinearCost c13({random(2, 2), random(2, 2)}, random(2, 1));
  LinearCost c23({random(4, 3), random(4, 2)}, random(4, 1));

  // The full problem (cost functions owned by the test).
  ceres::Problem::Options no_ownership;
  no_ownership.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  auto x1_full = x1;
  auto x2_full = x2;
  auto x3_full = x3;
  {
    ceres::Problem full(no_ownership);
    full.AddResidualBlock(&c1, nullptr, x1_full.data());
    full.AddResidualBlock(&c12, nullptr, x1_full.data(), x2_full.data());
    full.AddResidualBlock(&c13, nullptr, x1_full.data(), x3_full.data());
    full.AddResidualBlock(&c23, nullptr, x2_full.data(), x3_full.data());
    ceres::Solver::Summary summary;
    ceres::Solve(tightOptions(), &full, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
  }

  // Marginalise x1 at an arbitrary point (exact for a linear problem), then solve the rest.
  Marginalizer marginalizer;
  marginalizer.addResidualBlock(&c1, nullptr, {x1.data()});
  marginalizer.addResidualBlock(&c12, nullptr, {x1.data(), x2.data()});
  marginalizer.addResidualBlock(&c13, nullptr, {x1.data(), x3.data()});
  marginalizer.addResidualBlock(&c23, nullptr, {x2.data(), x3.data()});  // ignored: no x1
  const auto prior = marginalizer.marginalize({x1.data()});
  ASSERT_EQ(prior->blocks.size(), 2u);
  EXPECT_EQ(prior->blocks[0], x2.data());
  EXPECT_EQ(prior->blocks[1], x3.data());
  {
    ceres::Problem reduced(no_ownership);
    MarginalizationFactor prior_factor(prior);
    reduced.AddResidualBlock(&prior_factor, nullptr, x2.data(), x3.data());
    reduced.AddResidualBlock(&c23, nullptr, x2.data(), x3.data());
    ceres::Solver::Summary summary;
    ceres::Solve(tightOptions(), &reduced, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
  }
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(x2[k], x2_full[k], 1e-9);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(x3[k], x3_full[k], 1e-9);
}

// Relative pose measurement T_i^-1 T_j = (dp, dq), residual [R_i^T (p_j - p_i) - dp, 2 vec(dq^-1
// q_i^-1 q_j)] / sigma.
struct RelativePose {
  Eigen::Vector3d dp;
  Eigen::Quaterniond dq;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_i(a), p_j(b);
    Eigen::Map<const Eigen::Quaternion<T>> q_i(a + 3), q_j(b + 3);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = q_i.conjugate() * (p_j - p_i) - dp.cast<T>();
    r.template tail<3>() = T(2.0) * (dq.cast<T>().conjugate() * q_i.conjugate() * q_j).vec();
    r *= T(inv_sigma);
    return true;
  }
};

// Absolute pose measurement (anchors the chain).
struct AbsolutePose {
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
  template <typename T>
  bool operator()(const T* a, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(a);
    Eigen::Map<const Eigen::Quaternion<T>> q_a(a + 3);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = p_a - p.cast<T>();
    r.template tail<3>() = T(2.0) * (q.cast<T>().conjugate() * q_a).vec();
    return true;
  }
};

using Pose = std::array<double, 7>;

Pose pose(const Eigen::Vector3d& p, const Eigen::Vector3d& phi) {
  Pose x;
  setPose(p, quaternionExp(phi), x.data());
  return x;
}

ceres::CostFunction* relative(const Eigen::Vector3d& dp, const Eigen::Vector3d& dphi,
                              double inv_sigma) {
  return new ceres::AutoDiffCostFunction<RelativePose, 6, 7, 7>(
      new RelativePose{dp, quaternionExp(dphi), inv_sigma});
}

TEST(Marginalization, PoseChainKeepsEstimateAfterMarginalisingFirstPose) {
  const PoseManifold pm;
  // Slightly inconsistent measurements so that the optimum is a compromise; the 0-2 loop has a
  // Cauchy loss and a large error, so the robust correction is exercised.
  std::unique_ptr<ceres::CostFunction> anchor(new ceres::AutoDiffCostFunction<AbsolutePose, 6, 7>(
      new AbsolutePose{Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity()}));
  std::unique_ptr<ceres::CostFunction> r01(relative({1.0, 0.1, 0.0}, {0.0, 0.0, 0.3}, 10.0));
  std::unique_ptr<ceres::CostFunction> r12(relative({1.1, -0.1, 0.05}, {0.02, 0.0, 0.25}, 10.0));
  std::unique_ptr<ceres::CostFunction> r02(relative({2.3, 0.5, 0.0}, {0.0, 0.05, 0.5}, 5.0));
  ceres::CauchyLoss loss(1.0);

  Pose x0 = pose({0.1, 0, 0}, {0, 0, 0.1}), x1 = pose({1, 0.3, 0}, {0, 0, 0.2}),
       x2 = pose({2, 0.8, 0}, {0, 0, 0.6});
  ceres::Problem::Options no_ownership;
  no_ownership.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  no_ownership.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  no_ownership.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  {
    ceres::Problem full(no_ownership);
    full.AddResidualBlock(anchor.get(), nullptr, x0.data());
    full.AddResidualBlock(r01.get(), nullptr, x0.data(), x1.data());
    full.AddResidualBlock(r12.get(), nullptr, x1.data(), x2.data());
    full.AddResidualBlock(r02.get(), &loss, x0.data(), x2.data());
    for (Pose* x : {&x0, &x1, &x2}) full.SetManifold(x->data(), const_cast<PoseManifold*>(&pm));
    ceres::Solver::Summary summary;
    ceres::Solve(tightOptions(), &full, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
  }
  const Pose x1_full = x1, x2_full = x2;

  Marginalizer marginalizer;
  for (Pose* x : {&x0, &x1, &x2}) marginalizer.setManifold(x->data(), &pm);
  marginalizer.addResidualBlock(anchor.get(), nullptr, {x0.data()});
  marginalizer.addResidualBlock(r01.get(), nullptr, {x0.data(), x1.data()});
  marginalizer.addResidualBlock(r02.get(), &loss, {x0.data(), x2.data()});
  const auto prior = marginalizer.marginalize({x0.data()});
  EXPECT_EQ(prior->J.rows(), 12);  // 2 poses fully constrained

  // Re-solve the reduced problem from a perturbed start: same optimum.
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0.0, 0.05);
  for (Pose* x : {&x1, &x2}) {
    Eigen::Matrix<double, 6, 1> d;
    for (int k = 0; k < 6; ++k) d(k) = n(rng);
    Pose moved;
    pm.Plus(x->data(), d.data(), moved.data());
    *x = moved;
  }
  {
    ceres::Problem reduced(no_ownership);
    MarginalizationFactor prior_factor(prior);
    reduced.AddResidualBlock(&prior_factor, nullptr, x1.data(), x2.data());
    reduced.AddResidualBlock(r12.get(), nullptr, x1.data(), x2.data());
    for (Pose* x : {&x1, &x2}) reduced.SetManifold(x->data(), const_cast<PoseManifold*>(&pm));
    ceres::Solver::Summary summary;
    ceres::Solve(tightOptions(), &reduced, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
  }
  for (int k = 0; k < 7; ++k) {
    EXPECT_NEAR(x1[k], x1_full[k], 1e-8) << k;
    EXPECT_NEAR(x2[k], x2_full[k], 1e-8) << k;
  }
}

// The estimator's structure: a pose-like block p and landmark-like scalars l1..l4 marginalised,
// each landmark meeting p and a kept block, never another landmark. The landmarks go through
// the cheap per-block elimination, p through the dense one; the prior must equal the Schur
// complement computed densely here: J^T J = H*, J^T r = g*. l4 meets p and k2 but not k1, which
// lies between them: its update falls on blocks apart from each other, not one run of rows.
TEST(Marginalization, LandmarkStructureMatchesDenseSchurComplement) {
  std::mt19937 rng(7);
  auto random = [&](int rows, int cols) { return randomMatrix(rows, cols, rng); };
  std::array<double, 3> p{0.1, -0.2, 0.3}, k1{1.0, 0.5, -0.5};
  std::array<double, 2> k2{0.2, 0.4};
  std::array<std::array<double, 1>, 4> l{{{0.5}, {-0.7}, {1.2}, {0.9}}};
  // Global layout of the reference: [p(3) l1 l2 l3 l4 | k1(3) k2(2)].
  const int n_marg = 7, n_all = 12;
  std::vector<std::unique_ptr<LinearCost>> costs;
  std::vector<std::vector<int>> offsets;  // per cost, per block: global offset
  std::vector<std::vector<double*>> blocks;
  auto add = [&](std::vector<double*> b, std::vector<int> off, std::vector<int> sizes, int rows) {
    std::vector<Eigen::MatrixXd> A;
    for (int s : sizes) A.push_back(random(rows, s));
    costs.push_back(std::make_unique<LinearCost>(A, random(rows, 1)));
    blocks.push_back(std::move(b));
    offsets.push_back(std::move(off));
  };
  add({p.data()}, {0}, {3}, 3);  // p's own prior
  for (int i = 0; i < 3; ++i)    // two observations per landmark
    for (int obs = 0; obs < 2; ++obs)
      add({p.data(), l[i].data(), k1.data()}, {0, 3 + i, 7}, {3, 1, 3}, 2);
  for (int obs = 0; obs < 2; ++obs) add({p.data(), l[3].data(), k2.data()}, {0, 6, 10}, {3, 1, 2}, 2);
  add({p.data(), k2.data()}, {0, 10}, {3, 2}, 3);
  std::array<double, 2> fixed{0.3, 0.3};  // held constant: not part of the prior
  add({p.data(), fixed.data()}, {0, -1}, {3, 2}, 2);
  add({k1.data(), k2.data()}, {7, 10}, {3, 2}, 4);  // kept only: ignored by the marginaliser

  Marginalizer marginalizer;
  marginalizer.setConstant(fixed.data());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n_all, n_all);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n_all);
  for (size_t c = 0; c < costs.size(); ++c) {
    if (blocks[c][0] == k1.data()) continue;  // kept only: ignored by the marginaliser
    marginalizer.addResidualBlock(costs[c].get(), nullptr, blocks[c]);
    const auto& sizes = costs[c]->parameter_block_sizes();
    const int rows = costs[c]->num_residuals();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, n_all);
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jk;
    std::vector<double*> ptrs;
    for (int s : sizes) Jk.emplace_back(rows, s);
    for (auto& m : Jk) ptrs.push_back(m.data());
    Eigen::VectorXd r(rows);
    costs[c]->Evaluate(blocks[c].data(), r.data(), ptrs.data());
    for (size_t k = 0; k < sizes.size(); ++k)
      if (offsets[c][k] >= 0) J.middleCols(offsets[c][k], sizes[k]) = Jk[k];
    H += J.transpose() * J;
    g += J.transpose() * r;
  }
  const Eigen::MatrixXd Hmm_inv = H.topLeftCorner(n_marg, n_marg).inverse();
  const Eigen::MatrixXd Hkm = H.bottomLeftCorner(n_all - n_marg, n_marg);
  const Eigen::MatrixXd H_star = H.bottomRightCorner(5, 5) - Hkm * Hmm_inv * Hkm.transpose();
  const Eigen::VectorXd g_star = g.tail(5) - Hkm * Hmm_inv * g.head(n_marg);

  const auto prior =
      marginalizer.marginalize({p.data(), l[0].data(), l[1].data(), l[2].data(), l[3].data()});
  ASSERT_EQ(prior->blocks.size(), 2u);
  // The prior's kept order is first appearance: k1 (via a landmark residual), then k2.
  EXPECT_EQ(prior->blocks[0], k1.data());
  EXPECT_EQ(prior->blocks[1], k2.data());
  const Eigen::MatrixXd JtJ = prior->J.transpose() * prior->J;
  const Eigen::VectorXd Jtr = prior->J.transpose() * prior->r;
  EXPECT_LT((JtJ - H_star).norm(), 1e-9 * H_star.norm()) << JtJ << "\n\n" << H_star;
  EXPECT_LT((Jtr - g_star).norm(), 1e-9 * g_star.norm());
}

// A semi-definite Schur complement, as the estimator's always is (its position and yaw carry no
// information): x meets k1 and k2 only through differences (r = A (x - k) - b), so H* over
// [k1 | k2] is blind to moving both by the same amount. Its near-zero eigenvalues are dropped:
// the prior keeps rank 3, its square-root and information forms are the dense H* and g*, and
// it says nothing along the blind direction.
TEST(Marginalization, SemiDefiniteSchurComplementKeepsItsRankOnly) {
  std::mt19937 rng(11);
  auto random = [&](int rows, int cols) { return randomMatrix(rows, cols, rng); };
  std::array<double, 3> x{0.1, 0.2, 0.3}, k1{1.0, -1.0, 0.5}, k2{-0.5, 0.4, 2.0};
  const Eigen::MatrixXd A1 = random(4, 3), A2 = random(4, 3);
  LinearCost c1({A1, -A1}, random(4, 1)), c2({A2, -A2}, random(4, 1));
  Marginalizer marginalizer;
  marginalizer.addResidualBlock(&c1, nullptr, {x.data(), k1.data()});
  marginalizer.addResidualBlock(&c2, nullptr, {x.data(), k2.data()});
  const auto prior = marginalizer.marginalize({x.data()});

  // Dense reference over [x | k1 | k2].
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(8, 9);
  J.block(0, 0, 4, 3) = A1, J.block(0, 3, 4, 3) = -A1;
  J.block(4, 0, 4, 3) = A2, J.block(4, 6, 4, 3) = -A2;
  Eigen::VectorXd r(8);
  {
    const double* b1[] = {x.data(), k1.data()};
    const double* b2[] = {x.data(), k2.data()};
    c1.Evaluate(b1, r.data(), nullptr);
    c2.Evaluate(b2, r.data() + 4, nullptr);
  }
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::VectorXd g = J.transpose() * r;
  const Eigen::MatrixXd Hmm_inv = H.topLeftCorner(3, 3).inverse();
  const Eigen::MatrixXd Hkm = H.bottomLeftCorner(6, 3);
  const Eigen::MatrixXd H_star = H.bottomRightCorner(6, 6) - Hkm * Hmm_inv * Hkm.transpose();
  const Eigen::VectorXd g_star = g.tail(6) - Hkm * Hmm_inv * g.head(3);

  EXPECT_EQ(prior->J.rows(), 3);
  EXPECT_LT((prior->J.transpose() * prior->J - H_star).norm(), 1e-9 * H_star.norm());
  EXPECT_LT((prior->J.transpose() * prior->r - g_star).norm(), 1e-9 * (1.0 + g_star.norm()));
  EXPECT_LT((prior->H - prior->J.transpose() * prior->J).norm(), 1e-9 * H_star.norm());
  EXPECT_LT((prior->b - prior->J.transpose() * prior->r).norm(), 1e-9 * (1.0 + g_star.norm()));
  EXPECT_NEAR(prior->c, prior->r.squaredNorm(), 1e-12);
  // Moving k1 and k2 together changes nothing.
  Eigen::VectorXd together(6);
  together << 0.3, -0.2, 0.1, 0.3, -0.2, 0.1;
  EXPECT_LT((prior->J * together).norm(), 1e-9 * together.norm() * prior->J.norm());
  EXPECT_LT(std::abs(prior->b.dot(together)), 1e-9 * (1.0 + prior->b.norm()));
}

// A random dense linear prior over [pose a (6), quaternion q (3), Euclidean e (2), pose b (6)]
// (residual form J, r and its information form H, b, c), and values x away from its x0 (larger
// rotations make Jr^-1 matter): the generic Minus path (quaternion), the pose one and none.
struct PriorAwayFromX0 {
  PoseManifold pm;
  ceres::EigenQuaternionManifold quaternion_manifold;
  Pose a = pose({0, 0, 0}, {0.1, 0.2, -0.3}), b = pose({1, 2, 3}, {0.5, -0.1, 0.2});
  std::array<double, 4> q{};
  std::array<double, 2> e{1.0, -2.0};
  std::shared_ptr<MarginalizationPrior> prior = std::make_shared<MarginalizationPrior>();
  Pose a2{}, b2{};
  std::array<double, 4> q2{};
  std::array<double, 2> e2{1.5, -1.0};

  explicit PriorAwayFromX0(unsigned seed) {
    Eigen::Map<Eigen::Quaterniond>(q.data()) = quaternionExp(Eigen::Vector3d(0.3, 0.3, -0.2));
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    prior->blocks = {a.data(), q.data(), e.data(), b.data()};
    prior->sizes = {7, 4, 2, 7};
    prior->tangent_sizes = {6, 3, 2, 6};
    prior->tangent_offsets = {0, 6, 9, 11};
    prior->manifolds = {&pm, &quaternion_manifold, nullptr, &pm};
    for (size_t k = 0; k < prior->blocks.size(); ++k)
      prior->x0.emplace_back(prior->blocks[k], prior->blocks[k] + prior->sizes[k]);
    prior->J.resize(17, 17);
    prior->r.resize(17);
    for (int i = 0; i < prior->J.size(); ++i) prior->J.data()[i] = n(rng);
    for (int i = 0; i < 17; ++i) prior->r(i) = n(rng);
    prior->H = prior->J.transpose() * prior->J;
    prior->b = prior->J.transpose() * prior->r;
    prior->c = prior->r.squaredNorm();
    Eigen::Matrix<double, 6, 1> d;
    d << 0.1, -0.2, 0.3, 0.4, -0.3, 0.5;
    pm.Plus(a.data(), d.data(), a2.data());
    pm.Plus(b.data(), (-d).eval().data(), b2.data());
    const Eigen::Vector3d dq(0.2, -0.4, 0.1);
    quaternion_manifold.Plus(q.data(), dq.data(), q2.data());
  }
  std::vector<double*> x() { return {a2.data(), q2.data(), e2.data(), b2.data()}; }
};

TEST(Marginalization, PriorFactorJacobiansMatchNumericAwayFromLinearisationPoint) {
  PriorAwayFromX0 f(4);
  const MarginalizationFactor factor(f.prior);
  const auto result = testing::checkJacobians(factor, f.x(), {&f.pm, &f.quaternion_manifold, nullptr, &f.pm}, 1e-5);
  EXPECT_TRUE(result.ok) << result.report;
  // At x0 the residual is r_p.
  Eigen::VectorXd r(17);
  const double* at_x0[] = {f.a.data(), f.q.data(), f.e.data(), f.b.data()};
  ASSERT_TRUE(factor.Evaluate(at_x0, r.data(), nullptr));
  EXPECT_LT((r - f.prior->r).norm(), 1e-12);
}

// The information form the window solver uses (linearizePrior: cost, gradient D^T (b + H m) and
// Hessian D^T H D) must be the residual form's |r|^2 / 2, J_t^T r and J_t^T J_t, with J_t the
// residual form's tangent Jacobians (checked against numeric ones above), away from x0: through
// the pose blocks' own chain rule, the generic quaternion path and a Euclidean block.
TEST(Marginalization, InformationFormIsTheResidualFormsNormalEquationsAwayFromLinearisationPoint) {
  PriorAwayFromX0 f(9);
  const MarginalizationFactor factor(f.prior);
  const std::vector<double*> values = f.x();
  const std::vector<const double*> x(values.begin(), values.end());
  const MarginalizationPrior& prior = *f.prior;

  // The residual form's residual and tangent Jacobian at x.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::VectorXd r(17);
  std::vector<RowMajor> ambient;
  std::vector<double*> jacobians;
  for (int size : prior.sizes) ambient.emplace_back(17, size);
  for (RowMajor& J : ambient) jacobians.push_back(J.data());
  ASSERT_TRUE(factor.Evaluate(values.data(), r.data(), jacobians.data()));
  Eigen::MatrixXd J_t(17, 17);
  for (size_t k = 0; k < x.size(); ++k) {
    const ceres::Manifold* m = prior.manifolds[k];
    RowMajor plus = RowMajor::Identity(prior.sizes[k], prior.tangent_sizes[k]);
    if (m) {
      ASSERT_TRUE(m->PlusJacobian(x[k], plus.data()));
    }
    J_t.middleCols(prior.tangent_offsets[k], prior.tangent_sizes[k]) = ambient[k] * plus;
  }

  const PriorLinearization L = linearizePrior(prior, x, true);
  EXPECT_NEAR(L.cost, 0.5 * r.squaredNorm(), 1e-9 * r.squaredNorm());
  EXPECT_LT((L.gradient - J_t.transpose() * r).norm(), 1e-9 * (J_t.transpose() * r).norm());
  const Eigen::MatrixXd H = J_t.transpose() * J_t;
  EXPECT_LT((L.hessian - H).norm(), 1e-9 * H.norm()) << "linearizePrior:\n" << L.hessian << "\nJ_t^T J_t:\n" << H;
  // Without the Hessian: the same cost and gradient.
  const PriorLinearization cheap = linearizePrior(prior, x, false);
  EXPECT_EQ(cheap.cost, L.cost);
  EXPECT_EQ(cheap.gradient, L.gradient);
  EXPECT_EQ(cheap.hessian.size(), 0);
}

// A gauge correction turns and shifts the whole window (the estimator's removeGaugeDrift); the
// prior moved with it (moveWorldFrame) must cost at the moved states what it cost before, with
// its gradient turned alike. Left where it was linearised, it cost more there and pulled the window
// back by the correction in every solve (hybrid V1_01: 2-3 rejected steps per solve).
TEST(Marginalization, PriorMovedWithTheWorldFrameCostsTheSameAtTheMovedStates) {
  const PoseManifold pm;
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  // A pose, a speed-bias [v, ba, bg], and an extrinsic-like pose the move leaves alone.
  Pose pose_a = pose({1, -2, 0.5}, {0.2, -0.1, 0.7}), extrinsic = pose({0.1, 0, 0}, {0, 0.2, 0});
  std::array<double, 9> sb{0.5, -0.3, 0.1, 0.01, 0.02, -0.01, 0.001, -0.002, 0.003};
  auto prior = std::make_shared<MarginalizationPrior>();
  prior->blocks = {pose_a.data(), sb.data(), extrinsic.data()};
  prior->sizes = {7, 9, 7};
  prior->tangent_sizes = {6, 9, 6};
  prior->tangent_offsets = {0, 6, 15};
  prior->manifolds = {&pm, nullptr, &pm};
  for (size_t k = 0; k < prior->blocks.size(); ++k)
    prior->x0.emplace_back(prior->blocks[k], prior->blocks[k] + prior->sizes[k]);
  prior->J = randomMatrix(21, 21, rng);
  prior->r = randomMatrix(21, 1, rng);
  prior->H = prior->J.transpose() * prior->J;
  prior->b = prior->J.transpose() * prior->r;
  prior->c = prior->r.squaredNorm();

  // The states a solve left: away from x0.
  Eigen::Matrix<double, 6, 1> d;
  d << 0.1, -0.2, 0.3, 0.05, -0.1, 0.2;
  Pose a{}, e{};
  pm.Plus(pose_a.data(), d.data(), a.data());
  pm.Plus(extrinsic.data(), (0.1 * d).eval().data(), e.data());
  std::array<double, 9> v = sb;
  for (double& x : v) x += 0.05 * n(rng);
  const PriorLinearization before = linearizePrior(*prior, {a.data(), v.data(), e.data()}, false);

  // The gauge correction: a turn about world z and a shift, on the window's pose and velocity.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -1.2, 0.05);
  Pose a_moved{};
  setPose(R * posePosition(a.data()) + t, Eigen::Quaterniond(R) * poseRotation(a.data()),
          a_moved.data());
  std::array<double, 9> v_moved = v;
  Eigen::Map<Eigen::Vector3d>(v_moved.data()) = R * Eigen::Vector3d(v[0], v[1], v[2]);
  const std::vector<const double*> moved_states = {a_moved.data(), v_moved.data(), e.data()};

  const auto moved = moveWorldFrame(*prior, R, t, {pose_a.data()}, {sb.data()});
  const PriorLinearization after = linearizePrior(*moved, moved_states, false);
  EXPECT_NEAR(after.cost, before.cost, 1e-9 * before.cost);
  // Gradient in the tangent spaces: the world-frame parts (dp, dv) turn with R; the rotation (on
  // the right: in the body frame), the biases and the untouched extrinsic do not.
  Eigen::VectorXd expected = before.gradient;
  expected.segment<3>(0) = R * before.gradient.segment<3>(0);
  expected.segment<3>(6) = R * before.gradient.segment<3>(6);
  EXPECT_LT((after.gradient - expected).norm(), 1e-9 * expected.norm());
  EXPECT_EQ(moved->x0[2], prior->x0[2]) << "a block in neither list must not move";
  // The residual form moved alike: J' (x' [-] x0') = J (x [-] x0).
  const MarginalizationFactor factor_before(prior), factor_after(moved);
  Eigen::VectorXd r_before(21), r_after(21);
  const double* x_before[] = {a.data(), v.data(), e.data()};
  ASSERT_TRUE(factor_before.Evaluate(x_before, r_before.data(), nullptr));
  ASSERT_TRUE(factor_after.Evaluate(moved_states.data(), r_after.data(), nullptr));
  EXPECT_LT((r_after - r_before).norm(), 1e-9 * r_before.norm());
  // What the estimator did before: the prior left in place costs more at the moved states.
  const PriorLinearization unmoved = linearizePrior(*prior, moved_states, false);
  EXPECT_GT(unmoved.cost, 1.5 * before.cost);
}


// A cost that remembers where it was asked for Jacobians and where for residuals only (first
// value of its first block): first-estimate Jacobians must take the former at x0.
class RecordingCost : public ceres::CostFunction {
 public:
  explicit RecordingCost(const ceres::CostFunction* inner) : inner_(inner) {
    set_num_residuals(inner->num_residuals());
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    (jacobians ? jacobian_points : residual_points).push_back(x[0][0]);
    return inner_->Evaluate(x, residuals, jacobians);
  }
  mutable std::vector<double> jacobian_points, residual_points;

 private:
  const ceres::CostFunction* inner_;
};

// Blocks x1 .. x4 (Euclidean, 2 each) in a chain of linear residuals: marginalise x1 (a prior on
// x2, x3), move the values as a solve would, then marginalise x2 with that prior and the next
// residuals. Linear residuals: the Schur complement is exact at any point, so with and without
// first-estimate Jacobians the second prior must be the same quadratic; with them it is expanded
// about x3's first estimate (its value at the first marginalisation), not its current value.
struct TwoMarginalisations {
  std::mt19937 rng{11};
  std::array<double, 2> x1{0.5, -1.0}, x2{0.2, 0.1}, x3{-0.3, 0.4}, x4{1.0, 2.0};
  std::unique_ptr<LinearCost> c123, c234, c34;
  std::shared_ptr<const MarginalizationPrior> first;
  std::array<double, 2> x3_first{};

  TwoMarginalisations() {
    auto random = [&](int rows, int cols) { return randomMatrix(rows, cols, rng); };
    c123 = std::make_unique<LinearCost>(std::vector<Eigen::MatrixXd>{random(5, 2), random(5, 2), random(5, 2)},
                                        random(5, 1));
    c234 = std::make_unique<LinearCost>(std::vector<Eigen::MatrixXd>{random(5, 2), random(5, 2), random(5, 2)},
                                        random(5, 1));
    c34 = std::make_unique<LinearCost>(std::vector<Eigen::MatrixXd>{random(3, 2), random(3, 2)}, random(3, 1));
    Marginalizer m;
    m.addResidualBlock(c123.get(), nullptr, {x1.data(), x2.data(), x3.data()});
    first = m.marginalize({x1.data()});
    x3_first = x3;
    // A solve moved the kept states.
    x2 = {0.25, 0.05};
    x3 = {-0.1, 0.6};
    x4 = {0.9, 2.2};
  }
  std::shared_ptr<const MarginalizationPrior> second(bool first_estimates, const ceres::CostFunction* cost234) {
    Marginalizer m;
    m.addPrior(first, first_estimates);
    m.addResidualBlock(cost234, nullptr, {x2.data(), x3.data(), x4.data()});
    m.addResidualBlock(c34.get(), nullptr, {x3.data(), x4.data()});  // ignored: no x2
    return m.marginalize({x2.data()});
  }
};

double priorCost(const MarginalizationPrior& p, const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return linearizePrior(p, {a.data(), b.data()}, false).cost;
}

TEST(Marginalization, FirstEstimatePriorIsTheSameQuadraticAboutTheFirstEstimates) {
  TwoMarginalisations f;
  RecordingCost recorded(f.c234.get());
  const auto fej = f.second(true, &recorded);
  const auto plain = f.second(false, f.c234.get());
  ASSERT_EQ(fej->blocks.size(), 2u);
  ASSERT_EQ(fej->blocks[0], f.x3.data());
  // x3 keeps its first estimate; x4, new to the prior, is linearised where it is.
  EXPECT_EQ(fej->x0[0], std::vector<double>(f.x3_first.begin(), f.x3_first.end()));
  EXPECT_EQ(fej->x0[1], std::vector<double>(f.x4.begin(), f.x4.end()));
  EXPECT_EQ(plain->x0[0], std::vector<double>(f.x3.begin(), f.x3.end()));
  // The residual at the current value of x2 (its first block), the Jacobians at its first estimate.
  ASSERT_EQ(recorded.jacobian_points.size(), 1u);
  ASSERT_EQ(recorded.residual_points.size(), 1u);
  EXPECT_EQ(recorded.jacobian_points[0], f.first->x0[0][0]);
  EXPECT_EQ(recorded.residual_points[0], f.x2[0]);
  EXPECT_NE(f.first->x0[0][0], f.x2[0]);
  // The same quadratic: the same cost anywhere (and the same curvature).
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    std::array<double, 2> a{n(f.rng), n(f.rng)}, b{n(f.rng), n(f.rng)};
    const double expected = priorCost(*plain, a, b);
    EXPECT_NEAR(priorCost(*fej, a, b), expected, 1e-9 * std::max(1.0, expected));
  }
  EXPECT_LT((fej->H - plain->H).norm(), 1e-9 * plain->H.norm());
}

// A hand-worked case: one pose at p0 = (1, 2, 0), q0 = identity, and a speed-bias with v0 = (0, 3, 0),
// H diagonal 1 .. 15. The turn about z by one radian moves the pose by n = [z x p0, R0^T z] =
// [(-2, 1, 0), (0, 0, 1)] and the velocity by z x v0 = (-3, 0, 0):
// n^T H n = 1*4 + 2*1 + 6*1 + 7*9 = 75.
TEST(Marginalization, InformationAlongYawHandWorked) {
  const PoseManifold pm;
  Pose a = pose({1, 2, 0}, {0, 0, 0});
  std::array<double, 9> sb{0, 3, 0, 0.1, 0.2, 0.3, 0.01, 0.02, 0.03};
  MarginalizationPrior prior;
  prior.blocks = {a.data(), sb.data()};
  prior.sizes = {7, 9};
  prior.tangent_sizes = {6, 9};
  prior.tangent_offsets = {0, 6};
  prior.manifolds = {&pm, nullptr};
  prior.x0 = {std::vector<double>(a.begin(), a.end()), std::vector<double>(sb.begin(), sb.end())};
  prior.H = Eigen::VectorXd::LinSpaced(15, 1, 15).asDiagonal();
  prior.J = prior.H.cwiseSqrt();
  EXPECT_NEAR(informationAlongYaw(prior, {a.data()}, {sb.data()}), 75.0, 1e-12);
  // At the linearisation point, not at the block's current value.
  a[0] = 5;
  EXPECT_NEAR(informationAlongYaw(prior, {a.data()}, {sb.data()}), 75.0, 1e-12);
  // A block in neither list is invariant under the turn (an extrinsic).
  EXPECT_NEAR(informationAlongYaw(prior, {}, {sb.data()}), 63.0, 1e-12);
  // Turned about z, the pose's rotation perturbation is R0^T z: with q0 a quarter turn about x,
  // z maps to (0, 1, 0) in the body (rows 4 .. 6 of the diagonal: 5), and z x p0 is unchanged.
  Pose b = pose({1, 2, 0}, {M_PI / 2, 0, 0});
  prior.x0[0] = std::vector<double>(b.begin(), b.end());
  EXPECT_NEAR(informationAlongYaw(prior, {a.data()}, {sb.data()}), 4 + 2 + 5 + 63, 1e-9);
}
}  // namespace
}  // namespace adugs::vio

#pragma once
// Marginalisation with a linearised prior (VINS-Mono's MarginalizationInfo, Schur complement).
//   1. Collect the residual blocks that touch the blocks to marginalise (others are ignored).
//   2. Linearise them at the current values: whitened, robust-loss corrected (Triggs, as Ceres
//      does), Jacobians in each block's tangent space.
//   3. H = J^T J, g = J^T r over [marginalised | kept]; Schur complement:
//        H* = H_kk - H_km H_mm^+ H_mk,  g* = g_k - H_km H_mm^+ g_m.
//   4. H* = V S V^T with eigenvalues below a floor dropped: J_p = S^1/2 V^T, r_p = S^-1/2 V^T g*,
//      so that |r_p + J_p dx|^2 = dx^T H* dx + 2 g*^T dx + const.
// MarginalizationFactor turns the prior into a Ceres cost: r = r_p + J_p (x [-] x0), with [-] the
// blocks' manifold Minus (poses: PoseManifold).
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace adugs::vio {

struct MarginalizationPrior {
  // The kept blocks, by their address at marginalisation time (the caller maps them to the blocks
  // of the next window), their ambient and tangent sizes, manifolds (nullptr: Euclidean; not
  // owned, must outlive the prior) and values x0 at the linearisation point.
  std::vector<double*> blocks;
  std::vector<int> sizes, tangent_sizes, tangent_offsets;
  std::vector<const ceres::Manifold*> manifolds;
  std::vector<std::vector<double>> x0;
  Eigen::MatrixXd J;  // rank x tangent size
  Eigen::VectorXd r;  // rank

  int tangentSize() const { return static_cast<int>(J.cols()); }
};

class Marginalizer {
 public:
  // Blocks without a manifold are Euclidean. Not owned: must outlive the prior.
  void setManifold(const double* block, const ceres::Manifold* manifold);
  // A block held constant in the window (e.g. T_B_C when not estimated): left out of the prior,
  // and its Jacobians are not evaluated.
  void setConstant(const double* block) { constant_.push_back(block); }
  // Cost and loss (loss may be null) are not owned and must stay alive until marginalize().
  void addResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        std::vector<double*> blocks);
  // Linearises at the current block values and Schur-complements `marginalized` out.
  // Throws std::invalid_argument if nothing is kept, a cost fails, or the prior is empty.
  std::shared_ptr<const MarginalizationPrior> marginalize(
      const std::vector<const double*>& marginalized, double eigenvalue_floor = 1e-8) const;

 private:
  struct Residual {
    const ceres::CostFunction* cost;
    const ceres::LossFunction* loss;
    std::vector<double*> blocks;
  };
  std::vector<Residual> residuals_;
  std::vector<std::pair<const double*, const ceres::Manifold*>> manifolds_;
  std::vector<const double*> constant_;
  const ceres::Manifold* manifoldOf(const double* block) const;
};

// The prior as a cost on the kept blocks (in the order of prior.blocks).
class MarginalizationFactor : public ceres::CostFunction {
 public:
  explicit MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  const MarginalizationPrior& prior() const { return *prior_; }

 private:
  std::shared_ptr<const MarginalizationPrior> prior_;
};

// d Minus(Plus(x, delta), x0) / d delta at delta = 0 (tangent x tangent, row-major): exact for
// PoseManifold and Euclidean blocks, central differences for other manifolds.
Eigen::MatrixXd minusJacobianAt(const ceres::Manifold* manifold, int size, const double* x,
                                const double* x0);

}  // namespace adugs::vio

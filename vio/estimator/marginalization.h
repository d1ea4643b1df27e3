#pragma once
// Marginalisation with a linearised prior (VINS-Mono's MarginalizationInfo, Schur complement).
//   1. Collect the residual blocks that touch the blocks to marginalise (others are ignored).
//   2. Linearise them at the current values: whitened, robust-loss corrected (Triggs, as Ceres
//      does), Jacobians in each block's tangent space.
//   3. H = J^T J, g = J^T r over [marginalised | kept]; Schur complement:
//        H* = H_kk - H_km H_mm^+ H_mk,  g* = g_k - H_km H_mm^+ g_m.
//   4. H* = V S V^T with eigenvalues below a floor dropped: J_p = S^1/2 V^T, r_p = S^-1/2 V^T g*,
//      so that |r_p + J_p dx|^2 = dx^T H* dx + 2 g*^T dx + const.
// The prior is kept in both forms: the residual r = r_p + J_p (x [-] x0) (MarginalizationFactor,
// a Ceres cost; [-] the blocks' manifold Minus, poses: PoseManifold) and the information form
// H = J_p^T J_p, b = J_p^T r_p, c = |r_p|^2 that the window solver and the next marginalisation
// use directly (linearizePrior): a dense residual of rank rows would cost rank x n^2 per
// linearisation, the information form n^2.
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
  // Information form of the same cost: |r_p + J_p m|^2 = c + 2 b^T m + m^T H m.
  Eigen::MatrixXd H;  // tangent x tangent
  Eigen::VectorXd b;  // tangent
  double c = 0;

  int tangentSize() const { return static_cast<int>(J.cols()); }
};

// The prior at the current values x of its blocks (x[k] for prior.blocks[k]): with m = x [-] x0
// and D = d m / d delta (block diagonal, minusJacobianAt), the cost |r|^2 / 2 = (c + 2 b^T m +
// m^T H m) / 2, its gradient D^T (b + H m) and Gauss-Newton Hessian D^T H D in the blocks' tangent
// spaces (the prior's tangent layout).
struct PriorLinearization {
  double cost = 0;           // |r|^2 / 2
  Eigen::VectorXd gradient;  // tangent
  Eigen::MatrixXd hessian;   // tangent x tangent (empty unless asked for)
};
// With first_estimates, D is taken at x0 (the identity): the prior's Jacobian stays where it was
// linearised, as every other factor's does on the prior's blocks under first-estimate Jacobians
// (the cost and gradient still move with x).
PriorLinearization linearizePrior(const MarginalizationPrior& prior,
                                  const std::vector<const double*>& x, bool with_hessian,
                                  bool first_estimates = false);

// First-estimate Jacobians (FEJ; Huang, Mourikis and Roumeliotis; as Basalt and DSO keep a
// linearisation point per state in the prior): once a block is in the marginalisation prior, every
// Jacobian with respect to it is evaluated at the prior's linearisation point x0 of that block,
// while residuals and costs are evaluated at the current value. Then all the factors on a block
// agree on the point they are linearised at, and the linearised window keeps the true problem's
// unobservable rotation about gravity; Jacobians at the newest values instead give the prior
// information along it (doc/estimator.md, "First-estimate Jacobians").
// The point to evaluate a Jacobian of `block` at: its x0 in `prior` under FEJ, else the block.
const double* linearizationPoint(const MarginalizationPrior* prior, const double* block);

// Information the prior holds along a turn of the whole window about the world's z axis (gravity),
// which no measurement can see: n^T H n for the prior's tangent n of that turn by one radian at its
// linearisation point (a pose: [z x p0, R0^T z]; a speed-bias: [z x v0, 0, 0]; other blocks 0).
// Zero for a consistent prior; blocks in neither list count as invariant.
double informationAlongYaw(const MarginalizationPrior& prior,
                           const std::vector<const double*>& pose_blocks,
                           const std::vector<const double*>& speed_bias_blocks);

class Marginalizer {
 public:
  // Blocks without a manifold are Euclidean. Not owned: must outlive the prior.
  void setManifold(const double* block, const ceres::Manifold* manifold);
  // A block held constant in the window (e.g. T_B_C when not estimated): left out of the prior,
  // and its Jacobians are not evaluated.
  void setConstant(const double* block) { constant_.push_back(block); }
  // Cost and loss (loss may be null) are not owned and must stay alive until marginalize().
  void addResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        const std::vector<double*>& blocks);
  // The previous prior, linearised in its information form (not as a dense residual). Like a
  // residual block, it takes part only if it touches a marginalised block.
  // With first_estimate_jacobians, the residuals' Jacobians on the prior's blocks are evaluated
  // at its linearisation points (linearizationPoint above), and the new prior keeps those points.
  void addPrior(std::shared_ptr<const MarginalizationPrior> prior,
                bool first_estimate_jacobians = false) {
    prior_ = std::move(prior);
    first_estimates_ = first_estimate_jacobians;
  }
  // Linearises at the current block values and Schur-complements `marginalized` out.
  // Throws std::invalid_argument if nothing is kept, a cost fails, or the prior is empty.
  std::shared_ptr<const MarginalizationPrior> marginalize(
      const std::vector<const double*>& marginalized, double eigenvalue_floor = 1e-8) const;

 private:
  struct Residual {
    const ceres::CostFunction* cost;
    const ceres::LossFunction* loss;
    size_t first_block;  // its blocks: block_storage_[first_block ...], as many as the cost has
  };
  std::vector<Residual> residuals_;
  // Every residual's blocks in one array: a vector per residual was an allocation each, for
  // thousands of residuals per keyframe.
  std::vector<double*> block_storage_;
  double* const* blocksOf(const Residual& r) const { return block_storage_.data() + r.first_block; }
  std::vector<std::pair<const double*, const ceres::Manifold*>> manifolds_;
  std::vector<const double*> constant_;
  std::shared_ptr<const MarginalizationPrior> prior_;
  bool first_estimates_ = false;
  const ceres::Manifold* manifoldOf(const double* block) const;
};

// The same prior after the window's states went through a change of world frame
// x -> (R p + t, R q) on the pose blocks and v -> R v on the speed-bias blocks ([v, ba, bg]); every
// other block is unchanged. Its linearisation point moves with them and its information and
// gradient are rotated alike, so that the prior's cost at the moved states equals its cost at the
// states before (what a gauge correction of the window needs: the prior must not pull it back).
// Blocks of the prior that are in neither list are left as they are.
std::shared_ptr<const MarginalizationPrior> moveWorldFrame(
    const MarginalizationPrior& prior, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
    const std::vector<const double*>& pose_blocks,
    const std::vector<const double*>& speed_bias_blocks);

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

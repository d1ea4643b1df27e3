#pragma once
// The sliding window's nonlinear least-squares solver: Levenberg-Marquardt with the landmarks'
// inverse depths eliminated by the Schur complement, for the shape a visual-inertial window has:
// a few hundred one-value landmark blocks, each in residuals that otherwise touch only frame
// blocks, and a dense part of at most a few hundred tangent dimensions (poses, speed-biases,
// extrinsic, time offset).
//
// Cost: sum of rho(|r_i|^2) / 2 over the residual blocks (ceres::CostFunction with analytic
// Jacobians, the same objects Ceres takes; rho = the block's loss, identity without one) plus the
// marginalisation prior in its information form (marginalization.h), as ceres::Solve minimises
// it. Per iteration:
//   1. linearise every block at x (Jacobians in the tangent spaces, robust-corrected as Ceres);
//      accumulate the dense Hessian H_dd and gradient g_d, and per landmark l its h_l = J_l^T J_l,
//      g_l and coupling c_l = J_d^T J_l over the frame blocks it meets;
//   2. damp: H + D / mu with D = diag(H) clamped to [1e-6, 1e32] (Ceres' Levenberg-Marquardt);
//   3. Schur complement S = H_dd - sum_l c_l c_l^T / h_l (a rank-one update per landmark over its
//      frames only); S solved with the chain blocks (speed-biases) eliminated first by a
//      block-tridiagonal Cholesky, then a dense LLT of the rest (or one dense LLT of S when the
//      chain is coupled beyond neighbours); back-substitution d_l = -(g_l + c_l^T d_d) / h_l;
//   4. step, cost (and normal equations) at the candidate, accept if the gain ratio exceeds 1e-3
//      and update mu as Ceres does (mu /= max(1/3, 1 - (2 rho - 1)^3)), else restore x and
//      mu /= v, v *= 2.
// Stops after max_iterations (tried steps, as Ceres counts them), max_time_s, or when an accepted
// step changes the cost by less than function_tolerance relatively.
//
// Why not ceres::Solve with DENSE_SCHUR: for one-value e-blocks Ceres has no template
// specialisation of its Schur eliminator and the generic one, with its per-residual-block
// bookkeeping, cost about 6x the instructions per iteration of this loop on EuRoC-sized windows
// (callgrind, doc/estimator.md).
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "vio/estimator/marginalization.h"

namespace adugs::vio {

class TangentCostFunction;

struct WindowSolverOptions {
  int max_iterations = 8;
  double max_time_s = 0.2;            // checked after every iteration
  double function_tolerance = 1e-6;   // |cost change| / cost of an accepted step to stop at
  // mu (1 / damping) of the first step. 1e8: nearly the Gauss-Newton step, as Ceres' DOGLEG (which
  // the estimator used before) takes it; from Ceres' LM default of 1e4 the damping held the first
  // steps back and 8 iterations did not converge (street, 30 s: cost still falling 0.005 per step
  // at the 8th; with 1e8 the solves converge in 4.2 steps on average to lower costs).
  double initial_radius = 1e8;
};

struct WindowSolverSummary {
  int iterations = 0;  // steps tried (accepted or not)
  int successful = 0;
  double initial_cost = 0, final_cost = 0;
  bool converged = false;       // by function_tolerance
  bool time_limit_hit = false;  // stopped by max_time_s
  bool chain_first = false;     // the chain blocks were eliminated before the dense factorisation
};

class WindowSolver {
 public:
  // A frame block (pose [p, q] on its PoseManifold, speed-bias, extrinsic, time offset): part of
  // the dense system. Not owned; must outlive solve().
  void addBlock(double* x, int size, const ceres::Manifold* manifold = nullptr);
  // A frame block of a chain (the frames' speed-biases, in frame order): one that residuals and the
  // prior couple only with its neighbours in the chain and with frame blocks. The step eliminates
  // the chain after the landmarks by a block-tridiagonal Cholesky factorisation before the dense
  // one of the rest (poses, extrinsic, time offset): on a window of 15 the dense factorisation
  // shrinks from ~250 to ~100 dimensions. Any other coupling found (or a landmark meeting a chain
  // block) makes the step factor the whole dense part instead: same step, only slower.
  void addChainBlock(double* x, int size);
  // A one-value block eliminated by the Schur complement (a landmark's inverse depth). A residual
  // may touch at most one of them.
  void addLandmark(double* inverse_depth);
  // Held at its value (still evaluated).
  void setConstant(const double* x);
  // Every block must have been added. Cost and loss (may be null) are not owned.
  void addResidual(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                   const std::vector<double*>& blocks);
  // The marginalisation prior; its blocks must have been added. Not owned. With
  // first_estimate_jacobians every residual's Jacobians on a block of the prior are evaluated at
  // the prior's x0 of that block, and the prior's own without its Minus chain rule
  // (marginalization.h, linearizationPoint); costs and residuals stay at the current values.
  void setPrior(const MarginalizationPrior* prior, bool first_estimate_jacobians = false) {
    prior_ = prior;
    first_estimates_ = first_estimate_jacobians;
  }

  // Minimises from the blocks' current values, which it leaves at the best point found.
  // Throws std::invalid_argument when the structure is wrong (unknown block, two landmarks in a
  // residual); a cost that fails to evaluate ends the solve at the last good point.
  WindowSolverSummary solve(const WindowSolverOptions& options);

  // After solve(): the information of the frame blocks at their current values with the landmarks
  // eliminated (the undamped Schur complement), over the dense layout of tangentOffset(). Removing
  // the rows and columns of blocks held fixed and inverting gives the window's covariance of the
  // others given those (the estimator's consistency report). Empty if a cost fails to evaluate.
  Eigen::MatrixXd frameInformation();
  // A frame block's first row in that layout; -1 for constant blocks and landmarks.
  int tangentOffset(const double* block) const;

 private:
  struct Block {
    double* x = nullptr;
    int size = 0, tangent = 0;
    const ceres::Manifold* manifold = nullptr;
    bool constant = false;
    int landmark = -1;  // index into landmarks_ for eliminated blocks
    bool chain = false;  // added by addChainBlock
    int offset = -1;    // in the dense tangent vector (free frame blocks)
    std::vector<double> plus_jacobian;  // size x tangent, row-major, at the linearisation point
    std::vector<double> saved;          // value before a step
    const double* first_estimate = nullptr;  // where its Jacobians are evaluated (FEJ), or null
  };
  // A residual's per-block indices, stored inline: a window has thousands of residuals, rebuilt
  // for every solve, and two heap allocations each showed in the profile.
  static constexpr int kMaxBlocksPerResidual = 6;
  struct BlockIndices {
    int value[kMaxBlocksPerResidual] = {};
    int count = 0;
    int size() const { return count; }
    int operator[](int k) const { return value[k]; }
    int& operator[](int k) { return value[k]; }
    const int* begin() const { return value; }
    const int* end() const { return value + count; }
  };
  struct Residual {
    const ceres::CostFunction* cost = nullptr;
    const TangentCostFunction* tangent = nullptr;  // the same cost, when it is one
    const ceres::LossFunction* loss = nullptr;
    BlockIndices blocks;
    int landmark = -1;
    BlockIndices coupling;  // per block: offset in its landmark's coupling vector, or -1
    bool at_first_estimates = false;  // a block has a first estimate: two evaluations
  };
  struct Landmark {
    int block = -1;
    std::vector<int> dense_blocks;      // frame blocks it meets (distinct, by dense offset)
    std::vector<int> coupling_offsets;  // of each in its coupling vector
    int coupling_size = 0;
    int coupling_base = 0;  // start of its coupling vector in Linearization::coupling
  };
  // The normal equations at one point: dense part, and per landmark l the scalar h_l = J_l^T J_l,
  // g_l = J_l^T r and its coupling c_l = J_d^T J_l with the frame blocks it meets.
  struct Linearization {
    double cost = 0;
    Eigen::MatrixXd H;  // upper triangle accumulated, then mirrored
    Eigen::VectorXd g;
    std::vector<double> h, g_landmark, coupling;
  };

  int indexOf(const double* x) const;
  void prepare();
  // Cost at the current values into out->cost; with `linearize`, also the normal equations.
  // False if a cost function failed or gave a non-finite value.
  bool evaluate(bool linearize, Linearization* out);
  // S (upper triangle) and rhs of the reduced system of `at` damped for mu (infinite: undamped),
  // the landmarks eliminated, and the damping added to the diagonal.
  void eliminateLandmarks(const Linearization& at, double mu, Eigen::MatrixXd& S, Eigen::VectorXd& rhs,
                          Eigen::VectorXd& damping) const;
  // The damped Schur step of `at` for mu; false if the reduced system is not positive definite.
  bool computeStep(const Linearization& at, double mu, Eigen::VectorXd* step_dense,
                   std::vector<double>* step_landmarks, double* model_decrease);
  // Whether the residuals and the prior couple the free chain blocks only with their neighbours.
  bool chainIsTridiagonal() const;
  // Solves S x = rhs (S's upper triangle, the free chain blocks first) by eliminating the chain
  // block by block; overwrites S. False if S is not positive definite.
  bool solveChainFirst(Eigen::MatrixXd& S, const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;
  void applyStep(const Eigen::VectorXd& step_dense, const std::vector<double>& step_landmarks);
  // Whether a step from the current point to one of this cost ends the solve (function_tolerance).
  bool convergedBy(double cost, const WindowSolverOptions& options) const {
    return current_.cost - cost <= options.function_tolerance * current_.cost;
  }
  void restore();

  std::vector<Block> blocks_;
  std::unordered_map<const double*, int> index_;
  std::vector<Residual> residuals_;
  std::vector<Landmark> landmarks_;
  const MarginalizationPrior* prior_ = nullptr;
  bool first_estimates_ = false;
  std::vector<int> prior_blocks_;  // block index of each prior block
  int dense_size_ = 0;
  std::vector<int> chain_;  // the free chain blocks in order; offsets 0 .. chain_size_ - 1
  int chain_size_ = 0;
  bool chain_first_ = false;  // the step eliminates the chain first (chainIsTridiagonal)
  // At the current point and at a step's candidate (linearised there too: nearly every step is
  // accepted, so its Jacobians are the next iteration's).
  Linearization current_, candidate_;
  Eigen::MatrixXd schur_;  // the reduced system of the last step (workspace)
};

}  // namespace adugs::vio

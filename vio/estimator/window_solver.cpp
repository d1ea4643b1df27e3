#include "vio/estimator/window_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "vio/estimator/robust_correction.h"
#include "vio/estimator/tangent_cost_function.h"

namespace adugs::vio {
namespace {

// Largest residual and block this solver linearises (the IMU factor: 15 x 9); fixed-capacity
// Eigen storage keeps the per-residual work free of heap allocations.
constexpr int kMaxRows = TangentCostFunction::kMaxResiduals, kMaxCols = TangentCostFunction::kMaxTangentSize;

double clampDiagonal(double d) { return std::clamp(d, 1e-6, 1e32); }  // Ceres' LM bounds

// out (ta x tb, column-major with leading dimension ld) += A^T B for row-major A (rows x ta) and
// B (rows x tb). The common shapes (2-row reprojections on 6-value poses, 15-row IMU factors)
// go through fixed-size Eigen products, which compile to unrolled vector code; the blocks are too
// small for a dynamic-size product to pay its dispatch.
template <int R, int A, int B>
void addJtJFixed(const double* a, const double* b, double* out, int ld) {
  using RowMajorA = Eigen::Matrix<double, R, A, (A == 1 ? Eigen::ColMajor : Eigen::RowMajor)>;
  using RowMajorB = Eigen::Matrix<double, R, B, (B == 1 ? Eigen::ColMajor : Eigen::RowMajor)>;
  Eigen::Map<Eigen::Matrix<double, A, B>, 0, Eigen::OuterStride<>> o(out, A, B,
                                                                     Eigen::OuterStride<>(ld));
  // lazyProduct: Eigen sends products this size (15 x 9 x 9) to its blocked GEMM, whose packing
  // cost more than the product (1 % of a run's CPU in perf).
  o.noalias() += Eigen::Map<const RowMajorA>(a).transpose().lazyProduct(Eigen::Map<const RowMajorB>(b));
}

// The same for the two-row reprojection residuals, the most frequent case: a sum of two outer
// products, column by column (vector code along the contiguous columns of `out`; the product form
// above compiles to scalar code for these shapes and cost ~3x the instructions).
template <int A, int B>
void addJtJTwoRows(const double* a, const double* b, double* out, int ld) {
  Eigen::Map<Eigen::Matrix<double, A, B>, 0, Eigen::OuterStride<>> o(out, A, B,
                                                                     Eigen::OuterStride<>(ld));
  const Eigen::Map<const Eigen::Matrix<double, A, 1>> a0(a), a1(a + A);
  for (int j = 0; j < B; ++j) o.col(j) += a0 * b[j] + a1 * b[B + j];
}

void addJtJ(const double* a, int ta, const double* b, int tb, int rows, double* out, int ld) {
  if (rows == 2) {
    if (ta == 6 && tb == 6) return addJtJTwoRows<6, 6>(a, b, out, ld);
    if (ta == 6 && tb == 1) return addJtJTwoRows<6, 1>(a, b, out, ld);
  } else if (rows == 15) {
    if (ta == 6 && tb == 6) return addJtJFixed<15, 6, 6>(a, b, out, ld);
    if (ta == 6 && tb == 9) return addJtJFixed<15, 6, 9>(a, b, out, ld);
    if (ta == 9 && tb == 6) return addJtJFixed<15, 9, 6>(a, b, out, ld);
    if (ta == 9 && tb == 9) return addJtJFixed<15, 9, 9>(a, b, out, ld);
    if (ta == 6 && tb == 1) return addJtJFixed<15, 6, 1>(a, b, out, ld);
    if (ta == 9 && tb == 1) return addJtJFixed<15, 9, 1>(a, b, out, ld);
  }
  for (int j = 0; j < tb; ++j)
    for (int i = 0; i < ta; ++i) {
      double sum = 0;
      for (int k = 0; k < rows; ++k) sum += a[k * ta + i] * b[k * tb + j];
      out[i + j * ld] += sum;
    }
}

// out (ta x tb, column-major with leading dimension ld) -= a b^T. Poses meet poses in nearly every
// landmark's update: the 6 x 6 case as a fixed-size product (unrolled vector code).
void subtractOuter(const double* a, int ta, const double* b, int tb, double* out, int ld) {
  if (ta == 6 && tb == 6) {
    Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>> o(out, 6, 6,
                                                                      Eigen::OuterStride<>(ld));
    o.noalias() -= Eigen::Map<const Eigen::Matrix<double, 6, 1>>(a) *
                   Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b).transpose();
    return;
  }
  for (int j = 0; j < tb; ++j)
    for (int i = 0; i < ta; ++i) out[i + j * ld] -= a[i] * b[j];
}

// Ceres' corrector on a row-major Jacobian: J <- sqrt(rho') (J - alpha/|r|^2 r (r^T J)).
void correctJacobian(const RobustCorrection& c, const double* r, int rows, int cols, double* J) {
  double rJ[kMaxCols] = {0};
  for (int k = 0; k < rows; ++k)
    for (int i = 0; i < cols; ++i) rJ[i] += r[k] * J[k * cols + i];
  for (int k = 0; k < rows; ++k)
    for (int i = 0; i < cols; ++i)
      J[k * cols + i] = c.sqrt_rho1 * (J[k * cols + i] - c.alpha_sq_norm * r[k] * rJ[i]);
}

}  // namespace

void WindowSolver::addBlock(double* x, int size, const ceres::Manifold* manifold) {
  if (index_.count(x)) throw std::invalid_argument("WindowSolver: block added twice");
  if (size > kMaxCols || (manifold && manifold->AmbientSize() != size))
    throw std::invalid_argument("WindowSolver: block size not supported");
  Block b;
  b.x = x;
  b.size = size;
  b.tangent = manifold ? manifold->TangentSize() : size;
  b.manifold = manifold;
  index_[x] = static_cast<int>(blocks_.size());
  blocks_.push_back(std::move(b));
}

void WindowSolver::addChainBlock(double* x, int size) {
  addBlock(x, size);
  blocks_.back().chain = true;
}

void WindowSolver::addLandmark(double* inverse_depth) {
  addBlock(inverse_depth, 1);
  Landmark l;
  l.block = static_cast<int>(blocks_.size()) - 1;
  blocks_.back().landmark = static_cast<int>(landmarks_.size());
  landmarks_.push_back(std::move(l));
}

int WindowSolver::indexOf(const double* x) const {
  const auto it = index_.find(x);
  if (it == index_.end()) throw std::invalid_argument("WindowSolver: unknown parameter block");
  return it->second;
}

void WindowSolver::setConstant(const double* x) { blocks_[indexOf(x)].constant = true; }

void WindowSolver::addResidual(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                               const std::vector<double*>& blocks) {
  if (!cost || blocks.size() != cost->parameter_block_sizes().size() ||
      blocks.size() > static_cast<size_t>(kMaxBlocksPerResidual) || cost->num_residuals() > kMaxRows)
    throw std::invalid_argument("WindowSolver: cost function and blocks do not match");
  Residual r;
  r.cost = cost;
  r.tangent = dynamic_cast<const TangentCostFunction*>(cost);
  r.loss = loss;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const int b = indexOf(blocks[k]);
    if (blocks_[b].size != cost->parameter_block_sizes()[k])
      throw std::invalid_argument("WindowSolver: block size differs from the cost's");
    if (blocks_[b].landmark >= 0) {
      if (r.landmark >= 0) throw std::invalid_argument("WindowSolver: two landmarks in a residual");
      r.landmark = blocks_[b].landmark;
    }
    r.blocks[r.blocks.count++] = b;
  }
  residuals_.push_back(std::move(r));
}

void WindowSolver::prepare() {
  // Dense layout: the free chain blocks first (in the order added), then the other frame blocks.
  dense_size_ = 0;
  chain_.clear();
  for (int pass = 0; pass < 2; ++pass)
    for (size_t i = 0; i < blocks_.size(); ++i) {
      Block& b = blocks_[i];
      if (pass == 0) b.offset = -1;
      if (b.constant || b.landmark >= 0 || b.chain != (pass == 0)) continue;
      b.offset = dense_size_;
      dense_size_ += b.tangent;
      if (b.chain) chain_.push_back(static_cast<int>(i));
      if (b.manifold) b.plus_jacobian.resize(static_cast<size_t>(b.size * b.tangent));
    }
  chain_size_ = chain_.empty() ? 0 : blocks_[chain_.back()].offset + blocks_[chain_.back()].tangent;
  for (Landmark& l : landmarks_) {
    l.dense_blocks.clear();
    l.coupling_offsets.clear();
    l.coupling_size = 0;
  }
  for (Residual& r : residuals_) {
    r.coupling.count = r.blocks.count;
    std::fill(r.coupling.value, r.coupling.value + r.coupling.count, -1);
    if (r.landmark < 0 || blocks_[landmarks_[r.landmark].block].constant) continue;
    Landmark& l = landmarks_[r.landmark];
    for (int k = 0; k < r.blocks.size(); ++k) {
      const Block& b = blocks_[r.blocks[k]];
      if (b.offset < 0) continue;
      // Kept sorted by dense offset (inserted in place), so that the Schur update of block pair
      // (i <= j) lands in the upper triangle; coupling offsets in order of first appearance.
      const auto it = std::lower_bound(l.dense_blocks.begin(), l.dense_blocks.end(), b.offset,
                                       [&](int block, int offset) { return blocks_[block].offset < offset; });
      const auto at = it - l.dense_blocks.begin();
      if (it != l.dense_blocks.end() && *it == r.blocks[k]) {
        r.coupling[k] = l.coupling_offsets[static_cast<size_t>(at)];
      } else {
        l.dense_blocks.insert(it, r.blocks[k]);
        l.coupling_offsets.insert(l.coupling_offsets.begin() + at, l.coupling_size);
        r.coupling[k] = l.coupling_size;
        l.coupling_size += b.tangent;
      }
    }
  }
  int coupling_total = 0;
  for (Landmark& l : landmarks_) {
    l.coupling_base = coupling_total;
    coupling_total += l.coupling_size;
  }
  prior_blocks_.clear();
  for (Block& b : blocks_) b.first_estimate = nullptr;
  if (prior_)
    for (size_t k = 0; k < prior_->blocks.size(); ++k) {
      prior_blocks_.push_back(indexOf(prior_->blocks[k]));
      if (first_estimates_) blocks_[prior_blocks_.back()].first_estimate = prior_->x0[k].data();
    }
  for (Residual& r : residuals_)
    r.at_first_estimates = std::any_of(r.blocks.begin(), r.blocks.end(), [&](int b) {
      return blocks_[b].first_estimate && !blocks_[b].constant;
    });
  chain_first_ = !chain_.empty() && chainIsTridiagonal();
  for (Linearization* L : {&current_, &candidate_}) {
    L->H.resize(dense_size_, dense_size_);
    L->g.resize(dense_size_);
    L->h.resize(landmarks_.size());
    L->g_landmark.resize(landmarks_.size());
    L->coupling.resize(static_cast<size_t>(coupling_total));
  }
}

bool WindowSolver::chainIsTridiagonal() const {
  std::vector<int> position(blocks_.size(), -1);  // in chain_
  for (size_t k = 0; k < chain_.size(); ++k) position[static_cast<size_t>(chain_[k])] = static_cast<int>(k);
  auto neighbours = [&](const auto& blocks) {
    int lo = -1, hi = -1;
    for (int b : blocks) {
      const int k = position[static_cast<size_t>(b)];
      if (k < 0) continue;
      lo = lo < 0 ? k : std::min(lo, k);
      hi = std::max(hi, k);
    }
    return hi - lo <= 1;
  };
  for (const Residual& r : residuals_)
    if (!neighbours(r.blocks)) return false;
  if (prior_ && !neighbours(prior_blocks_)) return false;
  for (const Landmark& l : landmarks_)
    for (int b : l.dense_blocks)
      if (position[static_cast<size_t>(b)] >= 0) return false;
  return true;
}

bool WindowSolver::evaluate(bool linearize, Linearization* out) {
  if (linearize) {
    out->H.setZero();
    out->g.setZero();
    std::fill(out->h.begin(), out->h.end(), 0.0);
    std::fill(out->g_landmark.begin(), out->g_landmark.end(), 0.0);
    std::fill(out->coupling.begin(), out->coupling.end(), 0.0);
    for (Block& b : blocks_)
      if (b.offset >= 0 && b.manifold &&
          !b.manifold->PlusJacobian(b.first_estimate ? b.first_estimate : b.x, b.plus_jacobian.data()))
        return false;
  }
  double cost = 0;
  const double* params[kMaxBlocksPerResidual];
  const double* first_estimates[kMaxBlocksPerResidual];
  double* jacobians[kMaxBlocksPerResidual];
  // Tangent Jacobians, row-major rows x tangent, in fixed-capacity buffers (no allocation per
  // residual). TangentCostFunctions write them directly; other costs write ambient ones, turned
  // into tangent ones with the manifold's PlusJacobian.
  double J_ambient[kMaxBlocksPerResidual][kMaxRows * kMaxCols];
  double J[kMaxBlocksPerResidual][kMaxRows * kMaxCols];
  double r[kMaxRows];
  for (const Residual& res : residuals_) {
    const int rows = res.cost->num_residuals();
    const size_t n = static_cast<size_t>(res.blocks.size());
    bool any_jacobian = false;
    for (size_t k = 0; k < n; ++k) {
      const Block& b = blocks_[res.blocks[k]];
      params[k] = b.x;
      const bool wanted = linearize && !b.constant;
      jacobians[k] = !wanted ? nullptr : res.tangent ? J[k] : J_ambient[k];
      any_jacobian = any_jacobian || wanted;
    }
    double** jac = any_jacobian ? jacobians : nullptr;
    auto evaluateAt = [&](const double* const* at, double* residuals, double** jacobians_out) {
      return res.tangent ? res.tangent->EvaluateTangent(at, residuals, jacobians_out)
                         : res.cost->Evaluate(at, residuals, jacobians_out);
    };
    if (jac && res.at_first_estimates) {
      // The Jacobians at the first estimates (FEJ), the residual at the current values.
      for (size_t k = 0; k < n; ++k) {
        const Block& b = blocks_[res.blocks[k]];
        first_estimates[k] = b.first_estimate ? b.first_estimate : b.x;
      }
      double r_first[kMaxRows];
      if (!evaluateAt(first_estimates, r_first, jac)) return false;
      jac = nullptr;
    }
    if (!evaluateAt(params, r, jac)) return false;
    double sq_norm = 0;
    for (int i = 0; i < rows; ++i) sq_norm += r[i] * r[i];
    if (!std::isfinite(sq_norm)) return false;
    const RobustCorrection c = robustCorrection(res.loss, sq_norm);
    cost += 0.5 * c.rho;
    if (!any_jacobian) continue;

    for (size_t k = 0; k < n; ++k) {
      if (!jacobians[k]) continue;
      const Block& b = blocks_[res.blocks[k]];
      double* Jt = J[k];
      if (!res.tangent) {
        const double* Ja = J_ambient[k];
        if (b.manifold) {  // J_t = J_ambient * PlusJacobian
          const double* P = b.plus_jacobian.data();
          for (int row = 0; row < rows; ++row)
            for (int i = 0; i < b.tangent; ++i) {
              double sum = 0;
              for (int m = 0; m < b.size; ++m) sum += Ja[row * b.size + m] * P[m * b.tangent + i];
              Jt[row * b.tangent + i] = sum;
            }
        } else {
          std::copy(Ja, Ja + rows * b.size, Jt);
        }
      }
      if (!c.identity()) correctJacobian(c, r, rows, b.tangent, Jt);
    }
    if (!c.identity())
      for (int row = 0; row < rows; ++row) r[row] *= c.residual_scaling;

    int l_pos = -1;  // which block is the landmark's (when it is free)
    if (res.landmark >= 0)
      for (size_t k = 0; k < n; ++k)
        if (res.blocks[k] == landmarks_[res.landmark].block && jacobians[k])
          l_pos = static_cast<int>(k);
    for (size_t a = 0; a < n; ++a) {
      if (!jacobians[a] || static_cast<int>(a) == l_pos) continue;
      const Block& ba = blocks_[res.blocks[a]];
      addJtJ(J[a], ba.tangent, r, 1, rows, out->g.data() + ba.offset, dense_size_);
      for (size_t bi = 0; bi < n; ++bi) {
        if (!jacobians[bi] || static_cast<int>(bi) == l_pos) continue;
        const Block& bb = blocks_[res.blocks[bi]];
        if (bb.offset < ba.offset) continue;  // upper triangle only
        addJtJ(J[a], ba.tangent, J[bi], bb.tangent, rows,
               out->H.data() + static_cast<Eigen::Index>(bb.offset) * dense_size_ + ba.offset,
               dense_size_);
      }
    }
    if (l_pos >= 0) {
      const Landmark& l = landmarks_[res.landmark];
      const double* Jl = J[l_pos];  // rows x 1
      for (int row = 0; row < rows; ++row) {
        out->h[res.landmark] += Jl[row] * Jl[row];
        out->g_landmark[res.landmark] += Jl[row] * r[row];
      }
      for (size_t a = 0; a < n; ++a) {
        if (!jacobians[a] || static_cast<int>(a) == l_pos) continue;
        addJtJ(J[a], blocks_[res.blocks[a]].tangent, Jl, 1, rows,
               out->coupling.data() + l.coupling_base + res.coupling[a], l.coupling_size);
      }
    }
  }
  if (prior_) {
    std::vector<const double*> x;
    for (int b : prior_blocks_) x.push_back(blocks_[b].x);
    const PriorLinearization L = linearizePrior(*prior_, x, linearize, first_estimates_);
    if (!std::isfinite(L.cost)) return false;
    cost += L.cost;
    if (linearize) {
      for (size_t a = 0; a < prior_blocks_.size(); ++a) {
        const Block& ba = blocks_[prior_blocks_[a]];
        if (ba.offset < 0) continue;
        const int pa = prior_->tangent_offsets[a];
        out->g.segment(ba.offset, ba.tangent) += L.gradient.segment(pa, ba.tangent);
        for (size_t b = 0; b < prior_blocks_.size(); ++b) {
          const Block& bb = blocks_[prior_blocks_[b]];
          if (bb.offset < ba.offset) continue;
          out->H.block(ba.offset, bb.offset, ba.tangent, bb.tangent) +=
              L.hessian.block(pa, prior_->tangent_offsets[b], ba.tangent, bb.tangent);
        }
      }
    }
  }
  if (linearize) out->H.triangularView<Eigen::StrictlyLower>() = out->H.transpose();
  out->cost = cost;
  return std::isfinite(cost);
}

void WindowSolver::eliminateLandmarks(const Linearization& at, double mu, Eigen::MatrixXd& S,
                                      Eigen::VectorXd& rhs, Eigen::VectorXd& damping) const {
  const int n = dense_size_;
  S = at.H;
  rhs = -at.g;
  damping.resize(n);
  for (int i = 0; i < n; ++i) damping(i) = clampDiagonal(at.H(i, i)) / mu;
  S.diagonal() += damping;
  for (size_t k = 0; k < landmarks_.size(); ++k) {
    const Landmark& l = landmarks_[k];
    if (blocks_[l.block].constant) continue;
    const double h = at.h[k] + clampDiagonal(at.h[k]) / mu;
    if (!(h > 0)) continue;  // undamped and unseen: nothing to eliminate
    const double inv = 1.0 / h;
    const double* c = at.coupling.data() + l.coupling_base;
    const double g_inv = inv * at.g_landmark[k];
    // S -= c c^T / h over the blocks the landmark meets: block (i, j) -= c_i (c_j / h)^T for
    // i <= j (the upper triangle; a diagonal block is updated whole, its lower part is not read).
    double w[kMaxCols];
    for (size_t j = 0; j < l.dense_blocks.size(); ++j) {
      const Block& bj = blocks_[l.dense_blocks[j]];
      const double* cj = c + l.coupling_offsets[j];
      for (int b = 0; b < bj.tangent; ++b) {
        rhs[bj.offset + b] += g_inv * cj[b];
        w[b] = inv * cj[b];
      }
      double* column = S.data() + static_cast<Eigen::Index>(bj.offset) * n;
      for (size_t i = 0; i <= j; ++i) {
        const Block& bi = blocks_[l.dense_blocks[i]];
        subtractOuter(c + l.coupling_offsets[i], bi.tangent, w, bj.tangent, column + bi.offset, n);
      }
    }
  }
}

Eigen::MatrixXd WindowSolver::frameInformation() {
  if (!evaluate(true, &candidate_)) return {};
  Eigen::MatrixXd S;
  Eigen::VectorXd rhs, damping;
  eliminateLandmarks(candidate_, std::numeric_limits<double>::infinity(), S, rhs, damping);
  S.triangularView<Eigen::StrictlyLower>() = S.transpose();
  return S;
}

int WindowSolver::tangentOffset(const double* block) const { return blocks_[indexOf(block)].offset; }

bool WindowSolver::computeStep(const Linearization& at, double mu, Eigen::VectorXd* step_dense,
                               std::vector<double>* step_landmarks, double* model_decrease) {
  Eigen::MatrixXd& S = schur_;  // reused: no allocation per step
  Eigen::VectorXd rhs, damping;
  eliminateLandmarks(at, mu, S, rhs, damping);
  if (chain_first_) {
    if (!solveChainFirst(S, rhs, step_dense)) return false;
  } else {
    // In place: the factor overwrites S (its upper triangle), which the next step rebuilds.
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(S);
    if (llt.info() != Eigen::Success) return false;
    *step_dense = llt.solve(rhs);
  }
  if (!step_dense->allFinite()) return false;
  double decrease =
      0.5 * (-at.g.dot(*step_dense) + step_dense->dot(damping.cwiseProduct(*step_dense)));
  step_landmarks->assign(landmarks_.size(), 0.0);
  for (size_t k = 0; k < landmarks_.size(); ++k) {
    const Landmark& l = landmarks_[k];
    if (blocks_[l.block].constant) continue;
    const double d_l = clampDiagonal(at.h[k]) / mu;
    double coupled = at.g_landmark[k];
    for (size_t i = 0; i < l.dense_blocks.size(); ++i) {
      const Block& bi = blocks_[l.dense_blocks[i]];
      const double* ci = at.coupling.data() + l.coupling_base + l.coupling_offsets[i];
      for (int a = 0; a < bi.tangent; ++a) coupled += ci[a] * (*step_dense)[bi.offset + a];
    }
    const double step = -coupled / (at.h[k] + d_l);
    (*step_landmarks)[k] = step;
    decrease += 0.5 * (-at.g_landmark[k] * step + d_l * step * step);
  }
  *model_decrease = decrease;
  return std::isfinite(decrease);
}

bool WindowSolver::solveChainFirst(Eigen::MatrixXd& S, const Eigen::VectorXd& rhs,
                                   Eigen::VectorXd* x) const {
  // S = [S_cc S_cf; S_fc S_ff] (chain c first, frame blocks f) with S_cc block-tridiagonal.
  // S_cc = U^T U with U block-bidiagonal (U_kk, U_k,k+1); Y = U^-T S_cf and z = U^-T rhs_c are
  // written over S_cf's rows block by block; then (S_ff - Y^T Y) x_f = rhs_f - Y^T z, and
  // U x_c = z - Y x_f backwards.
  const int n = dense_size_, nc = chain_size_, nf = n - nc;
  const size_t m = chain_.size();
  Eigen::VectorXd z = rhs.head(nc);
  for (size_t k = 0; k < m; ++k) {
    const Block& b = blocks_[chain_[k]];
    const int o = b.offset, t = b.tangent;
    if (k > 0) {  // what block k-1's row contributes to row k
      const Block& a = blocks_[chain_[k - 1]];
      const auto U_prev = S.block(a.offset, o, a.tangent, t);
      S.block(o, o, t, t).noalias() -= U_prev.transpose() * U_prev;
      S.block(o, nc, t, nf).noalias() -= U_prev.transpose() * S.block(a.offset, nc, a.tangent, nf);
      z.segment(o, t).noalias() -= U_prev.transpose() * z.segment(a.offset, a.tangent);
    }
    auto S_kk = S.block(o, o, t, t);
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(S_kk);  // S_kk <- U_kk
    if (llt.info() != Eigen::Success) return false;
    const auto U_kk_T = S_kk.triangularView<Eigen::Upper>().transpose();
    if (k + 1 < m) {
      const Block& next = blocks_[chain_[k + 1]];
      U_kk_T.solveInPlace(S.block(o, next.offset, t, next.tangent));
    }
    U_kk_T.solveInPlace(S.block(o, nc, t, nf));
    U_kk_T.solveInPlace(z.segment(o, t));
  }
  const auto Y = S.block(0, nc, nc, nf);
  auto S_ff = S.block(nc, nc, nf, nf);
  S_ff.selfadjointView<Eigen::Upper>().rankUpdate(Y.transpose(), -1.0);
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(S_ff);
  if (llt.info() != Eigen::Success) return false;
  x->resize(n);
  x->tail(nf) = llt.solve(rhs.tail(nf) - Y.transpose() * z);
  for (size_t k = m; k-- > 0;) {
    const Block& b = blocks_[chain_[k]];
    const int o = b.offset, t = b.tangent;
    Eigen::VectorXd v = z.segment(o, t) - S.block(o, nc, t, nf) * x->tail(nf);
    if (k + 1 < m) {
      const Block& next = blocks_[chain_[k + 1]];
      v.noalias() -= S.block(o, next.offset, t, next.tangent) * x->segment(next.offset, next.tangent);
    }
    S.block(o, o, t, t).triangularView<Eigen::Upper>().solveInPlace(v);
    x->segment(o, t) = v;
  }
  return true;
}

void WindowSolver::applyStep(const Eigen::VectorXd& step_dense,
                             const std::vector<double>& step_landmarks) {
  double moved[kMaxCols];
  for (Block& b : blocks_) {
    if (b.constant) continue;
    b.saved.assign(b.x, b.x + b.size);
    const double* delta =
        b.landmark >= 0 ? &step_landmarks[static_cast<size_t>(b.landmark)] : step_dense.data() + b.offset;
    if (b.manifold) {
      b.manifold->Plus(b.x, delta, moved);
      std::copy(moved, moved + b.size, b.x);
    } else {
      for (int i = 0; i < b.size; ++i) b.x[i] += delta[i];
    }
  }
}

void WindowSolver::restore() {
  for (Block& b : blocks_)
    if (!b.constant) std::copy(b.saved.begin(), b.saved.end(), b.x);
}

WindowSolverSummary WindowSolver::solve(const WindowSolverOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  prepare();
  WindowSolverSummary summary;
  summary.chain_first = chain_first_;
  if (!evaluate(true, &current_)) return summary;
  summary.initial_cost = summary.final_cost = current_.cost;
  double mu = options.initial_radius, nu = 2.0;
  Eigen::VectorXd step_dense;
  std::vector<double> step_landmarks;
  while (summary.iterations < options.max_iterations) {
    ++summary.iterations;
    // The candidate's normal equations are only needed if another step may follow: not after the
    // last step, and most likely not after a step whose predicted decrease is already within the
    // tolerance (the step that ends a converging solve: a third of the linearisations at ~2.5
    // steps per solve). For that one the cost decides first, the normal equations follow only
    // if the solve goes on; the cost is the same either way (same residual code), so the solve
    // takes the same steps.
    const bool last = summary.iterations >= options.max_iterations || elapsed() >= options.max_time_s;
    double model_decrease = 0;
    bool accepted = false;
    if (computeStep(current_, mu, &step_dense, &step_landmarks, &model_decrease) &&
        model_decrease > 0) {
      applyStep(step_dense, step_landmarks);
      const bool expect_last =
          last || model_decrease <= options.function_tolerance * current_.cost;
      accepted = evaluate(!expect_last, &candidate_) &&
                 (current_.cost - candidate_.cost) / model_decrease > 1e-3;
      if (accepted && expect_last && !last && !convergedBy(candidate_.cost, options))
        accepted = evaluate(true, &candidate_);
      if (!accepted) restore();
    }
    if (accepted) {
      const double rho = (current_.cost - candidate_.cost) / model_decrease;
      summary.converged = convergedBy(candidate_.cost, options);
      std::swap(current_, candidate_);
      ++summary.successful;
      mu = std::min(mu / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)), 1e16);
      nu = 2.0;
      if (summary.converged) break;
    } else {
      mu = std::max(mu / nu, 1e-32);
      nu *= 2.0;
    }
    if (elapsed() >= options.max_time_s) {
      summary.time_limit_hit = summary.iterations < options.max_iterations;
      break;
    }
  }
  summary.final_cost = current_.cost;
  return summary;
}

}  // namespace adugs::vio

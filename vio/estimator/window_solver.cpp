#include "vio/estimator/window_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "vio/estimator/robust_correction.h"

namespace adugs::vio {
namespace {

// Largest residual and block this solver linearises (the IMU factor: 15 x 9); fixed-capacity
// Eigen storage keeps the per-residual work free of heap allocations.
constexpr int kMaxRows = 15, kMaxCols = 9, kMaxBlocksPerResidual = 6;

double clampDiagonal(double d) { return std::clamp(d, 1e-6, 1e32); }  // Ceres' LM bounds

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
  r.loss = loss;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const int b = indexOf(blocks[k]);
    if (blocks_[b].size != cost->parameter_block_sizes()[k])
      throw std::invalid_argument("WindowSolver: block size differs from the cost's");
    if (blocks_[b].landmark >= 0) {
      if (r.landmark >= 0) throw std::invalid_argument("WindowSolver: two landmarks in a residual");
      r.landmark = blocks_[b].landmark;
    }
    r.blocks.push_back(b);
  }
  residuals_.push_back(std::move(r));
}

void WindowSolver::prepare() {
  dense_size_ = 0;
  for (Block& b : blocks_) {
    b.offset = -1;
    if (b.constant || b.landmark >= 0) continue;
    b.offset = dense_size_;
    dense_size_ += b.tangent;
    if (b.manifold) b.plus_jacobian.resize(static_cast<size_t>(b.size * b.tangent));
  }
  for (Landmark& l : landmarks_) {
    l.dense_blocks.clear();
    l.coupling_offsets.clear();
    l.coupling_size = 0;
  }
  for (Residual& r : residuals_) {
    r.coupling.assign(r.blocks.size(), -1);
    if (r.landmark < 0 || blocks_[landmarks_[r.landmark].block].constant) continue;
    Landmark& l = landmarks_[r.landmark];
    for (size_t k = 0; k < r.blocks.size(); ++k) {
      const Block& b = blocks_[r.blocks[k]];
      if (b.offset < 0) continue;
      const auto it = std::find(l.dense_blocks.begin(), l.dense_blocks.end(), r.blocks[k]);
      if (it != l.dense_blocks.end()) {
        r.coupling[k] = l.coupling_offsets[it - l.dense_blocks.begin()];
      } else {
        l.dense_blocks.push_back(r.blocks[k]);
        l.coupling_offsets.push_back(l.coupling_size);
        r.coupling[k] = l.coupling_size;
        l.coupling_size += b.tangent;
      }
    }
  }
  for (Landmark& l : landmarks_) {
    // Sorted by dense offset, so that the Schur update of block pair (i <= j) lands in the upper
    // triangle.
    std::vector<size_t> order(l.dense_blocks.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return blocks_[l.dense_blocks[a]].offset < blocks_[l.dense_blocks[b]].offset;
    });
    std::vector<int> blocks, offsets;
    for (size_t i : order) {
      blocks.push_back(l.dense_blocks[i]);
      offsets.push_back(l.coupling_offsets[i]);
    }
    l.dense_blocks.swap(blocks);
    l.coupling_offsets.swap(offsets);
    l.coupling.resize(l.coupling_size);
  }
  prior_blocks_.clear();
  if (prior_)
    for (const double* b : prior_->blocks) prior_blocks_.push_back(indexOf(b));
  H_.resize(dense_size_, dense_size_);
  g_.resize(dense_size_);
}

bool WindowSolver::evaluate(bool linearize, double* total_cost) {
  if (linearize) {
    H_.setZero();
    g_.setZero();
    for (Landmark& l : landmarks_) {
      l.h = l.g = 0;
      l.coupling.setZero();
    }
    for (Block& b : blocks_)
      if (b.offset >= 0 && b.manifold && !b.manifold->PlusJacobian(b.x, b.plus_jacobian.data()))
        return false;
  }
  double cost = 0;
  const double* params[kMaxBlocksPerResidual];
  double* jacobians[kMaxBlocksPerResidual];
  // Ambient Jacobians as the cost writes them (row-major), then tangent ones (column-major: the
  // products below are dot products of contiguous columns). Fixed capacity, no allocation; the
  // blocks are so small (2 x 6 for most) that Eigen's product dispatch would cost more than the
  // arithmetic.
  double J_ambient[kMaxBlocksPerResidual][kMaxRows * kMaxCols];
  double J[kMaxBlocksPerResidual][kMaxRows * kMaxCols];
  double r[kMaxRows];
  double* H = H_.data();
  const int ld = dense_size_;
  for (const Residual& res : residuals_) {
    const int rows = res.cost->num_residuals();
    const size_t n = res.blocks.size();
    bool any_jacobian = false;
    for (size_t k = 0; k < n; ++k) {
      const Block& b = blocks_[res.blocks[k]];
      params[k] = b.x;
      const bool wanted = linearize && !b.constant;
      jacobians[k] = wanted ? J_ambient[k] : nullptr;
      any_jacobian = any_jacobian || wanted;
    }
    if (!res.cost->Evaluate(params, r, any_jacobian ? jacobians : nullptr)) return false;
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
      const double* Ja = J_ambient[k];
      if (b.manifold) {  // J_t = J_ambient * PlusJacobian
        const double* P = b.plus_jacobian.data();
        for (int i = 0; i < b.tangent; ++i)
          for (int row = 0; row < rows; ++row) {
            double sum = 0;
            for (int m = 0; m < b.size; ++m) sum += Ja[row * b.size + m] * P[m * b.tangent + i];
            Jt[row + i * rows] = sum;
          }
      } else {
        for (int i = 0; i < b.tangent; ++i)
          for (int row = 0; row < rows; ++row) Jt[row + i * rows] = Ja[row * b.size + i];
      }
      if (res.loss) {  // J' = sqrt(rho') (J - alpha/|r|^2 r r^T J)
        for (int i = 0; i < b.tangent; ++i) {
          double* col = Jt + i * rows;
          double rj = 0;
          for (int row = 0; row < rows; ++row) rj += r[row] * col[row];
          for (int row = 0; row < rows; ++row)
            col[row] = c.sqrt_rho1 * (col[row] - c.alpha_sq_norm * r[row] * rj);
        }
      }
    }
    if (res.loss)
      for (int row = 0; row < rows; ++row) r[row] *= c.residual_scaling;
    auto dot = [rows](const double* a, const double* b) {
      double sum = 0;
      for (int row = 0; row < rows; ++row) sum += a[row] * b[row];
      return sum;
    };

    int l_pos = -1;  // which block is the landmark's (when it is free)
    if (res.landmark >= 0)
      for (size_t k = 0; k < n; ++k)
        if (res.blocks[k] == landmarks_[res.landmark].block && jacobians[k])
          l_pos = static_cast<int>(k);
    for (size_t a = 0; a < n; ++a) {
      if (!jacobians[a] || static_cast<int>(a) == l_pos) continue;
      const Block& ba = blocks_[res.blocks[a]];
      for (int i = 0; i < ba.tangent; ++i) g_[ba.offset + i] += dot(J[a] + i * rows, r);
      for (size_t bi = 0; bi < n; ++bi) {
        if (!jacobians[bi] || static_cast<int>(bi) == l_pos) continue;
        const Block& bb = blocks_[res.blocks[bi]];
        if (bb.offset < ba.offset) continue;  // upper triangle only
        for (int j = 0; j < bb.tangent; ++j) {
          double* column = H + (bb.offset + j) * ld + ba.offset;
          const double* Jb = J[bi] + j * rows;
          for (int i = 0; i < ba.tangent; ++i) column[i] += dot(J[a] + i * rows, Jb);
        }
      }
    }
    if (l_pos >= 0) {
      Landmark& l = landmarks_[res.landmark];
      const double* Jl = J[l_pos];
      l.h += dot(Jl, Jl);
      l.g += dot(Jl, r);
      for (size_t a = 0; a < n; ++a) {
        if (!jacobians[a] || static_cast<int>(a) == l_pos) continue;
        double* coupling = l.coupling.data() + res.coupling[a];
        for (int i = 0; i < blocks_[res.blocks[a]].tangent; ++i) coupling[i] += dot(J[a] + i * rows, Jl);
      }
    }
  }
  if (prior_) {
    std::vector<const double*> x;
    for (int b : prior_blocks_) x.push_back(blocks_[b].x);
    const PriorLinearization L = linearizePrior(*prior_, x, linearize);
    if (!std::isfinite(L.cost)) return false;
    cost += L.cost;
    if (linearize) {
      for (size_t a = 0; a < prior_blocks_.size(); ++a) {
        const Block& ba = blocks_[prior_blocks_[a]];
        if (ba.offset < 0) continue;
        const int pa = prior_->tangent_offsets[a];
        g_.segment(ba.offset, ba.tangent) += L.gradient.segment(pa, ba.tangent);
        for (size_t b = 0; b < prior_blocks_.size(); ++b) {
          const Block& bb = blocks_[prior_blocks_[b]];
          if (bb.offset < ba.offset) continue;
          H_.block(ba.offset, bb.offset, ba.tangent, bb.tangent) +=
              L.hessian.block(pa, prior_->tangent_offsets[b], ba.tangent, bb.tangent);
        }
      }
    }
  }
  if (linearize) H_.triangularView<Eigen::StrictlyLower>() = H_.transpose();
  *total_cost = cost;
  return std::isfinite(cost);
}

bool WindowSolver::computeStep(double mu, Eigen::VectorXd* step_dense,
                               std::vector<double>* step_landmarks, double* model_decrease) const {
  const int n = dense_size_;
  Eigen::MatrixXd S = H_;
  Eigen::VectorXd rhs = -g_;
  Eigen::VectorXd damping(n);
  for (int i = 0; i < n; ++i) damping(i) = clampDiagonal(H_(i, i)) / mu;
  S.diagonal() += damping;
  for (const Landmark& l : landmarks_) {
    if (blocks_[l.block].constant) continue;
    const double inv = 1.0 / (l.h + clampDiagonal(l.h) / mu);
    // S -= c c^T / h over the blocks the landmark meets (upper triangle, column by column).
    for (size_t j = 0; j < l.dense_blocks.size(); ++j) {
      const Block& bj = blocks_[l.dense_blocks[j]];
      const double* cj = l.coupling.data() + l.coupling_offsets[j];
      for (int b = 0; b < bj.tangent; ++b) {
        rhs[bj.offset + b] += inv * l.g * cj[b];
        const double w = inv * cj[b];
        double* column = S.data() + static_cast<Eigen::Index>(bj.offset + b) * n;
        for (size_t i = 0; i <= j; ++i) {
          const Block& bi = blocks_[l.dense_blocks[i]];
          const double* ci = l.coupling.data() + l.coupling_offsets[i];
          const int rows = i == j ? b + 1 : bi.tangent;  // diagonal block: its upper part
          for (int a = 0; a < rows; ++a) column[bi.offset + a] -= w * ci[a];
        }
      }
    }
  }
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Upper> llt(S);
  if (llt.info() != Eigen::Success) return false;
  *step_dense = llt.solve(rhs);
  if (!step_dense->allFinite()) return false;
  double decrease = 0.5 * (-g_.dot(*step_dense) + step_dense->dot(damping.cwiseProduct(*step_dense)));
  step_landmarks->assign(landmarks_.size(), 0.0);
  for (size_t k = 0; k < landmarks_.size(); ++k) {
    const Landmark& l = landmarks_[k];
    if (blocks_[l.block].constant) continue;
    const double d_l = clampDiagonal(l.h) / mu;
    double coupled = l.g;
    for (size_t i = 0; i < l.dense_blocks.size(); ++i) {
      const Block& bi = blocks_[l.dense_blocks[i]];
      coupled += l.coupling.segment(l.coupling_offsets[i], bi.tangent)
                     .dot(step_dense->segment(bi.offset, bi.tangent));
    }
    const double step = -coupled / (l.h + d_l);
    (*step_landmarks)[k] = step;
    decrease += 0.5 * (-l.g * step + d_l * step * step);
  }
  *model_decrease = decrease;
  return std::isfinite(decrease);
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
  double cost = 0;
  if (!evaluate(true, &cost)) return summary;
  summary.initial_cost = summary.final_cost = cost;
  double mu = options.initial_radius, nu = 2.0;
  Eigen::VectorXd step_dense;
  std::vector<double> step_landmarks;
  while (summary.iterations < options.max_iterations) {
    ++summary.iterations;
    double model_decrease = 0, new_cost = 0;
    bool accepted = false;
    if (computeStep(mu, &step_dense, &step_landmarks, &model_decrease) && model_decrease > 0) {
      applyStep(step_dense, step_landmarks);
      if (evaluate(false, &new_cost) && (cost - new_cost) / model_decrease > 1e-3) {
        accepted = true;
      } else {
        restore();
      }
    }
    if (accepted) {
      const double rho = (cost - new_cost) / model_decrease;
      summary.converged = cost - new_cost <= options.function_tolerance * cost;
      cost = new_cost;
      ++summary.successful;
      mu = std::min(mu / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)), 1e16);
      nu = 2.0;
      if (summary.converged) break;
      if (summary.iterations < options.max_iterations && elapsed() < options.max_time_s &&
          !evaluate(true, &cost)) {
        break;  // Jacobians failed at an accepted point: keep it, stop here
      }
    } else {
      mu = std::max(mu / nu, 1e-32);
      nu *= 2.0;
    }
    if (elapsed() >= options.max_time_s) {
      summary.time_limit_hit = summary.iterations < options.max_iterations;
      break;
    }
  }
  summary.final_cost = cost;
  return summary;
}

}  // namespace adugs::vio

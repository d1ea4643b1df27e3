#include "vio/marginalization.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "vio/pose_manifold.h"
#include "vio/so3.h"

namespace adugs::vio {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

int tangentSizeOf(const ceres::Manifold* m, int size) { return m ? m->TangentSize() : size; }

// Ambient Jacobian (rows x size) -> tangent Jacobian (rows x tangent).
Eigen::MatrixXd toTangent(const RowMajorMatrix& J, const ceres::Manifold* m, const double* x) {
  if (!m) return J;
  RowMajorMatrix plus(m->AmbientSize(), m->TangentSize());
  if (!m->PlusJacobian(x, plus.data())) throw std::invalid_argument("PlusJacobian failed");
  return J * plus;
}

// Symmetric pseudo-inverse with eigenvalues below `floor` dropped.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double floor) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  const Eigen::VectorXd s =
      es.eigenvalues().unaryExpr([&](double v) { return v > floor ? 1.0 / v : 0.0; });
  return (es.eigenvectors() * s.asDiagonal()).lazyProduct(es.eigenvectors().transpose());
}

}  // namespace

void Marginalizer::setManifold(const double* block, const ceres::Manifold* manifold) {
  for (auto& [b, m] : manifolds_) {
    if (b == block) {
      m = manifold;
      return;
    }
  }
  manifolds_.emplace_back(block, manifold);
}

const ceres::Manifold* Marginalizer::manifoldOf(const double* block) const {
  for (const auto& [b, m] : manifolds_)
    if (b == block) return m;
  return nullptr;
}

void Marginalizer::addResidualBlock(const ceres::CostFunction* cost,
                                    const ceres::LossFunction* loss, std::vector<double*> blocks) {
  if (!cost || blocks.size() != cost->parameter_block_sizes().size())
    throw std::invalid_argument("Marginalizer: cost function and blocks do not match");
  residuals_.push_back({cost, loss, std::move(blocks)});
}

std::shared_ptr<const MarginalizationPrior> Marginalizer::marginalize(
    const std::vector<const double*>& marginalized, double eigenvalue_floor) const {
  auto isMarginalized = [&](const double* b) {
    return std::find(marginalized.begin(), marginalized.end(), b) != marginalized.end();
  };
  // Blocks in order of first appearance: marginalised ones first, then kept.
  struct Block {
    double* address;
    int size, tangent, offset;
    const ceres::Manifold* manifold;
  };
  std::vector<Block> marg, kept;
  std::vector<const Residual*> used;
  for (const Residual& res : residuals_) {
    if (std::none_of(res.blocks.begin(), res.blocks.end(), isMarginalized)) continue;
    used.push_back(&res);
    for (size_t k = 0; k < res.blocks.size(); ++k) {
      double* b = res.blocks[k];
      auto& list = isMarginalized(b) ? marg : kept;
      if (std::any_of(list.begin(), list.end(), [&](const Block& x) { return x.address == b; }))
        continue;
      const int size = res.cost->parameter_block_sizes()[k];
      const ceres::Manifold* m = manifoldOf(b);
      list.push_back({b, size, tangentSizeOf(m, size), 0, m});
    }
  }
  if (kept.empty()) throw std::invalid_argument("Marginalizer: no kept block");
  int n_marg = 0, n_total = 0;
  for (Block& b : marg) b.offset = n_marg, n_marg += b.tangent;
  n_total = n_marg;
  for (Block& b : kept) b.offset = n_total, n_total += b.tangent;
  auto find = [&](const double* address) -> const Block& {
    for (const Block& b : marg)
      if (b.address == address) return b;
    for (const Block& b : kept)
      if (b.address == address) return b;
    throw std::logic_error("Marginalizer: unknown block");
  };

  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n_total, n_total);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n_total);
  for (const Residual* res : used) {
    const int n_res = res->cost->num_residuals();
    const std::vector<int32_t>& sizes = res->cost->parameter_block_sizes();
    Eigen::VectorXd r(n_res);
    std::vector<RowMajorMatrix> J_amb(sizes.size());
    std::vector<double*> jac_ptrs(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) {
      J_amb[k].resize(n_res, sizes[k]);
      jac_ptrs[k] = J_amb[k].data();
    }
    if (!res->cost->Evaluate(res->blocks.data(), r.data(), jac_ptrs.data()))
      throw std::invalid_argument("Marginalizer: a cost function failed to evaluate");
    std::vector<Eigen::MatrixXd> J(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k)
      J[k] = toTangent(J_amb[k], find(res->blocks[k]).manifold, res->blocks[k]);

    if (res->loss) {
      // Ceres' Corrector: scale r and J so that the Gauss-Newton model matches rho's curvature.
      const double sq_norm = r.squaredNorm();
      double rho[3];
      res->loss->Evaluate(sq_norm, rho);
      const double sqrt_rho1 = std::sqrt(rho[1]);
      double residual_scaling = sqrt_rho1, alpha_sq_norm = 0.0;
      if (sq_norm > 0.0 && rho[2] > 0.0) {
        const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * sq_norm * rho[2] / rho[1]);
        residual_scaling = sqrt_rho1 / (1.0 - alpha);
        alpha_sq_norm = alpha / sq_norm;
      }
      for (auto& Jk : J) Jk = sqrt_rho1 * (Jk - alpha_sq_norm * r * (r.transpose() * Jk));
      r *= residual_scaling;
    }
    for (size_t a = 0; a < sizes.size(); ++a) {
      const Block& ba = find(res->blocks[a]);
      g.segment(ba.offset, ba.tangent) += J[a].transpose() * r;
      for (size_t b = 0; b < sizes.size(); ++b) {
        const Block& bb = find(res->blocks[b]);
        H.block(ba.offset, bb.offset, ba.tangent, bb.tangent) += J[a].transpose() * J[b];
      }
    }
  }

  const int n_kept = n_total - n_marg;
  const Eigen::MatrixXd Hmm_inv = pseudoInverse(
      0.5 * (H.topLeftCorner(n_marg, n_marg) + H.topLeftCorner(n_marg, n_marg).transpose()),
      eigenvalue_floor);
  // lazyProduct: these sizes (tens to a few hundred) do not pay for Eigen's OpenMP GEMM, whose
  // spinning threads cost more than the product on a loaded 2-core machine.
  const Eigen::MatrixXd Hkm = H.bottomLeftCorner(n_kept, n_marg);
  const Eigen::MatrixXd Hkm_Hmm_inv = Hkm.lazyProduct(Hmm_inv);
  Eigen::MatrixXd H_star =
      H.bottomRightCorner(n_kept, n_kept) - Hkm_Hmm_inv.lazyProduct(Hkm.transpose());
  H_star = 0.5 * (H_star + H_star.transpose()).eval();
  const Eigen::VectorXd g_star = g.tail(n_kept) - Hkm_Hmm_inv * g.head(n_marg);

  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(H_star);
  std::vector<int> rows;
  for (int k = 0; k < n_kept; ++k)
    if (es.eigenvalues()(k) > eigenvalue_floor) rows.push_back(k);
  if (rows.empty()) throw std::invalid_argument("Marginalizer: the prior carries no information");

  auto prior = std::make_shared<MarginalizationPrior>();
  prior->J.resize(static_cast<int>(rows.size()), n_kept);
  prior->r.resize(static_cast<int>(rows.size()));
  for (size_t i = 0; i < rows.size(); ++i) {
    const double s = es.eigenvalues()(rows[i]);
    const Eigen::VectorXd v = es.eigenvectors().col(rows[i]);
    prior->J.row(static_cast<int>(i)) = std::sqrt(s) * v.transpose();
    prior->r(static_cast<int>(i)) = v.dot(g_star) / std::sqrt(s);
  }
  for (const Block& b : kept) {
    prior->blocks.push_back(b.address);
    prior->sizes.push_back(b.size);
    prior->tangent_sizes.push_back(b.tangent);
    prior->tangent_offsets.push_back(b.offset - n_marg);
    prior->manifolds.push_back(b.manifold);
    prior->x0.emplace_back(b.address, b.address + b.size);
  }
  return prior;
}

Eigen::MatrixXd minusJacobianAt(const ceres::Manifold* manifold, int size, const double* x,
                                const double* x0) {
  if (!manifold) return Eigen::MatrixXd::Identity(size, size);
  if (dynamic_cast<const PoseManifold*>(manifold)) {
    // Minus = [p - p0, Log(q0^-1 q)]; q -> q Exp(d) moves the log by Jr^-1(log) d.
    Eigen::MatrixXd D = Eigen::MatrixXd::Identity(6, 6);
    const Eigen::Vector3d phi = quaternionLog(poseRotation(x0).conjugate() * poseRotation(x));
    D.bottomRightCorner(3, 3) = rightJacobianInverse(phi);
    return D;
  }
  const int n = manifold->TangentSize(), m = manifold->AmbientSize();
  constexpr double kStep = 1e-6;
  Eigen::MatrixXd D(n, n);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n), xp(m), xm(m), yp(n), ym(n);
  for (int k = 0; k < n; ++k) {
    delta(k) = kStep;
    manifold->Plus(x, delta.data(), xp.data());
    delta(k) = -kStep;
    manifold->Plus(x, delta.data(), xm.data());
    delta(k) = 0.0;
    manifold->Minus(xp.data(), x0, yp.data());
    manifold->Minus(xm.data(), x0, ym.data());
    D.col(k) = (yp - ym) / (2.0 * kStep);
  }
  return D;
}

MarginalizationFactor::MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior)
    : prior_(std::move(prior)) {
  set_num_residuals(static_cast<int>(prior_->r.size()));
  for (int size : prior_->sizes) mutable_parameter_block_sizes()->push_back(size);
}

bool MarginalizationFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  const MarginalizationPrior& p = *prior_;
  Eigen::VectorXd dx(p.tangentSize());
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    double* out = dx.data() + p.tangent_offsets[k];
    if (p.manifolds[k]) {
      if (!p.manifolds[k]->Minus(parameters[k], p.x0[k].data(), out)) return false;
    } else {
      for (int i = 0; i < p.sizes[k]; ++i) out[i] = parameters[k][i] - p.x0[k][i];
    }
  }
  Eigen::Map<Eigen::VectorXd>(residuals, p.r.size()) = p.r + p.J * dx;
  if (!jacobians) return true;
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    if (!jacobians[k]) continue;
    const ceres::Manifold* m = p.manifolds[k];
    Eigen::MatrixXd J_tangent = p.J.middleCols(p.tangent_offsets[k], p.tangent_sizes[k]) *
                                minusJacobianAt(m, p.sizes[k], parameters[k], p.x0[k].data());
    Eigen::Map<RowMajorMatrix> J(jacobians[k], p.r.size(), p.sizes[k]);
    if (!m) {
      J = J_tangent;
    } else {
      // Lift to ambient coordinates: MinusJacobian(x) * PlusJacobian(x) = I.
      RowMajorMatrix lift(m->TangentSize(), m->AmbientSize());
      if (!m->MinusJacobian(parameters[k], lift.data())) return false;
      J = J_tangent * lift;
    }
  }
  return true;
}

}  // namespace adugs::vio

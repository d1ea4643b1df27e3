#include "vio/estimator/marginalization.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "vio/estimator/pose_manifold.h"
#include "vio/estimator/robust_correction.h"
#include "vio/imu/so3.h"

namespace adugs::vio {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

int tangentSizeOf(const ceres::Manifold* m, int size) { return m ? m->TangentSize() : size; }

// Ambient Jacobian (rows x size) -> tangent Jacobian (rows x tangent), into buffers reused from
// one residual to the next (`plus`: scratch for the manifold's PlusJacobian).
void toTangent(const RowMajorMatrix& J, const ceres::Manifold* m, const double* x,
               RowMajorMatrix* plus, Eigen::MatrixXd* tangent) {
  if (!m) {
    *tangent = J;
    return;
  }
  plus->resize(m->AmbientSize(), m->TangentSize());
  if (!m->PlusJacobian(x, plus->data())) throw std::invalid_argument("PlusJacobian failed");
  // A few rows: Eigen's GEMM dispatch would cost more than the sums.
  tangent->noalias() = J.lazyProduct(*plus);
}

// The rotation block of a pose's Minus Jacobian: Minus = [p - p0, Log(q0^-1 q)], and q -> q Exp(d)
// moves the log by Jr^-1(log) d (the translation block is the identity).
Eigen::Matrix3d poseMinusRotationJacobian(const double* x, const double* x0) {
  return rightJacobianInverse(quaternionLog(poseRotation(x0).conjugate() * poseRotation(x)));
}

// Symmetric pseudo-inverse with eigenvalues below `floor` dropped.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double floor) {
  if (A.rows() == 1)  // a landmark's inverse depth: most calls
    return Eigen::MatrixXd::Constant(1, 1, A(0, 0) > floor ? 1.0 / A(0, 0) : 0.0);
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
                                    const ceres::LossFunction* loss,
                                    const std::vector<double*>& blocks) {
  if (!cost || blocks.size() != cost->parameter_block_sizes().size())
    throw std::invalid_argument("Marginalizer: cost function and blocks do not match");
  residuals_.push_back({cost, loss, block_storage_.size()});
  block_storage_.insert(block_storage_.end(), blocks.begin(), blocks.end());
}

std::shared_ptr<const MarginalizationPrior> Marginalizer::marginalize(
    const std::vector<const double*>& marginalized, double eigenvalue_floor) const {
  const std::unordered_set<const double*> is_marginalized(marginalized.begin(), marginalized.end());
  // Blocks in order of first appearance: marginalised ones first, then kept.
  struct Block {
    double* address;
    int size, tangent, offset;
    const ceres::Manifold* manifold;
  };
  std::vector<Block> marg, kept;
  std::unordered_map<const double*, std::pair<bool, size_t>> where;  // marginalised?, index
  const std::unordered_set<const double*> is_constant(constant_.begin(), constant_.end());
  std::vector<const Residual*> used;
  for (const Residual& res : residuals_) {
    double* const* res_blocks = blocksOf(res);
    const size_t n_blocks = res.cost->parameter_block_sizes().size();
    if (std::none_of(res_blocks, res_blocks + n_blocks,
                     [&](const double* b) { return is_marginalized.count(b) > 0; }))
      continue;
    used.push_back(&res);
    for (size_t k = 0; k < n_blocks; ++k) {
      double* b = res_blocks[k];
      if (where.count(b) || is_constant.count(b)) continue;
      const bool m = is_marginalized.count(b) > 0;
      auto& list = m ? marg : kept;
      const int size = res.cost->parameter_block_sizes()[k];
      const ceres::Manifold* manifold = manifoldOf(b);
      where[b] = {m, list.size()};
      list.push_back({b, size, tangentSizeOf(manifold, size), 0, manifold});
    }
  }
  // The previous prior takes part like a residual block: if it touches a marginalised block.
  const bool use_prior =
      prior_ && std::any_of(prior_->blocks.begin(), prior_->blocks.end(),
                            [&](const double* b) { return is_marginalized.count(b) > 0; });
  if (use_prior) {
    for (size_t k = 0; k < prior_->blocks.size(); ++k) {
      double* b = prior_->blocks[k];
      if (where.count(b) || is_constant.count(b)) continue;
      const bool m = is_marginalized.count(b) > 0;
      auto& list = m ? marg : kept;
      where[b] = {m, list.size()};
      list.push_back({b, prior_->sizes[k], prior_->tangent_sizes[k], 0, prior_->manifolds[k]});
    }
  }
  if (kept.empty()) throw std::invalid_argument("Marginalizer: no kept block");
  int n_marg = 0, n_total = 0;
  for (Block& b : marg) b.offset = n_marg, n_marg += b.tangent;
  n_total = n_marg;
  for (Block& b : kept) b.offset = n_total, n_total += b.tangent;

  // Normal equations of the linearised residuals over [marginalised | kept]; constant blocks
  // take no part (null Jacobian pointers: the cost skips them).
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n_total, n_total);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n_total);
  // Buffers reused across residuals (their sizes change only between kinds of residual).
  Eigen::VectorXd r;
  Eigen::RowVectorXd rtJ;
  RowMajorMatrix plus;
  std::vector<RowMajorMatrix> J_amb;
  std::vector<Eigen::MatrixXd> J;
  std::vector<double*> jac_ptrs;
  std::vector<const Block*> blocks;
  const MarginalizationPrior* fej = first_estimates_ ? prior_.get() : nullptr;
  std::vector<const double*> lin_ptrs;
  Eigen::VectorXd lin_r;
  for (const Residual* res : used) {
    double* const* res_blocks = blocksOf(*res);
    const int n_res = res->cost->num_residuals();
    const std::vector<int32_t>& sizes = res->cost->parameter_block_sizes();
    const size_t n_blocks = sizes.size();
    r.resize(n_res);
    J_amb.resize(n_blocks);
    J.resize(n_blocks);
    jac_ptrs.assign(n_blocks, nullptr);
    blocks.assign(n_blocks, nullptr);
    for (size_t k = 0; k < n_blocks; ++k) {
      const auto it = where.find(res_blocks[k]);
      if (it == where.end()) continue;  // constant
      blocks[k] = it->second.first ? &marg[it->second.second] : &kept[it->second.second];
      J_amb[k].resize(n_res, sizes[k]);
      jac_ptrs[k] = J_amb[k].data();
    }
    // Under first-estimate Jacobians the blocks of the previous prior are linearised at its x0:
    // the Jacobians there, the residual at the current values.
    bool at_first_estimates = false;
    lin_ptrs.resize(n_blocks);
    for (size_t k = 0; k < n_blocks; ++k) {
      lin_ptrs[k] = linearizationPoint(fej, res_blocks[k]);
      at_first_estimates = at_first_estimates || lin_ptrs[k] != res_blocks[k];
    }
    if (at_first_estimates) {
      lin_r.resize(n_res);
      if (!res->cost->Evaluate(lin_ptrs.data(), lin_r.data(), jac_ptrs.data()) ||
          !res->cost->Evaluate(res_blocks, r.data(), nullptr))
        throw std::invalid_argument("Marginalizer: a cost function failed to evaluate");
    } else if (!res->cost->Evaluate(res_blocks, r.data(), jac_ptrs.data())) {
      throw std::invalid_argument("Marginalizer: a cost function failed to evaluate");
    }
    for (size_t k = 0; k < n_blocks; ++k)
      if (blocks[k]) toTangent(J_amb[k], blocks[k]->manifold, lin_ptrs[k], &plus, &J[k]);

    if (res->loss) {
      // J <- sqrt(rho') (J - alpha r r^T J / |r|^2), coefficient by coefficient: as one Eigen
      // expression its outer product went through a heap temporary per block.
      const RobustCorrection c = robustCorrection(res->loss, r.squaredNorm());
      for (size_t k = 0; k < n_blocks; ++k) {
        if (!blocks[k]) continue;
        Eigen::MatrixXd& Jk = J[k];
        rtJ.noalias() = r.transpose() * Jk;
        for (Eigen::Index j = 0; j < Jk.cols(); ++j)
          for (Eigen::Index i = 0; i < Jk.rows(); ++i)
            Jk(i, j) = c.sqrt_rho1 * (Jk(i, j) - (c.alpha_sq_norm * r(i)) * rtJ(j));
      }
      r *= c.residual_scaling;
    }
    for (size_t a = 0; a < n_blocks; ++a) {
      if (!blocks[a]) continue;
      const Block& ba = *blocks[a];
      g.segment(ba.offset, ba.tangent).noalias() += J[a].transpose() * r;
      for (size_t b = 0; b < n_blocks; ++b) {
        if (!blocks[b]) continue;
        const Block& bb = *blocks[b];
        // The upper triangle only (mirrored below: J_b^T J_a is the transpose, coefficient for
        // coefficient). Products of 2- to 15-row Jacobians, thousands per keyframe: coefficient by
        // coefficient, not through Eigen's GEMM (which showed in the profile for these sizes).
        if (bb.offset < ba.offset) continue;
        H.block(ba.offset, bb.offset, ba.tangent, bb.tangent).noalias() += J[a].transpose().lazyProduct(J[b]);
      }
    }
  }
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();

  if (use_prior) {
    std::vector<const double*> x(prior_->blocks.begin(), prior_->blocks.end());
    const PriorLinearization L = linearizePrior(*prior_, x, true, first_estimates_);
    for (size_t a = 0; a < prior_->blocks.size(); ++a) {
      const auto wa = where.find(prior_->blocks[a]);
      if (wa == where.end()) continue;  // constant
      const Block& ba = wa->second.first ? marg[wa->second.second] : kept[wa->second.second];
      const int oa = prior_->tangent_offsets[a];
      g.segment(ba.offset, ba.tangent) += L.gradient.segment(oa, ba.tangent);
      for (size_t b = 0; b < prior_->blocks.size(); ++b) {
        const auto wb = where.find(prior_->blocks[b]);
        if (wb == where.end()) continue;
        const Block& bb = wb->second.first ? marg[wb->second.second] : kept[wb->second.second];
        H.block(ba.offset, bb.offset, ba.tangent, bb.tangent) +=
            L.hessian.block(oa, prior_->tangent_offsets[b], ba.tangent, bb.tangent);
      }
    }
  }

  // Schur complement in two steps. Marginalised blocks that do not meet one another (the
  // landmarks hosted in the oldest frame: each only meets poses) go first, each through its own
  // tiny inverse and only where it couples; a dense pseudo-inverse then handles the rest (the
  // frame's pose and speed-bias). Same result as one dense pseudo-inverse of all of H_mm, which
  // cost ~11 ms (eigen-decomposition of ~200 x 200) per keyframe on EuRoC-like windows.
  std::vector<const Block*> by_size;
  for (const Block& b : marg) by_size.push_back(&b);
  std::stable_sort(by_size.begin(), by_size.end(),
                   [](const Block* a, const Block* b) { return a->tangent < b->tangent; });
  std::vector<const Block*> independent, dense;
  for (const Block* b : by_size) {
    const bool meets = std::any_of(independent.begin(), independent.end(), [&](const Block* c) {
      return !H.block(b->offset, c->offset, b->tangent, c->tangent).isZero(0.0);
    });
    (meets ? dense : independent).push_back(b);
  }
  // Remaining indices: the dense marginalised blocks, then every kept one.
  std::vector<int> rest;
  for (const Block* b : dense)
    for (int i = 0; i < b->tangent; ++i) rest.push_back(b->offset + i);
  const int n_dense = static_cast<int>(rest.size());
  for (int i = n_marg; i < n_total; ++i) rest.push_back(i);
  const int n_rest = static_cast<int>(rest.size());
  Eigen::MatrixXd H_rest(n_rest, n_rest);
  Eigen::VectorXd g_rest(n_rest);
  for (int j = 0; j < n_rest; ++j) {
    g_rest(j) = g(rest[j]);
    for (int i = 0; i < n_rest; ++i) H_rest(i, j) = H(rest[i], rest[j]);
  }
  for (const Block* s : independent) {
    const Eigen::MatrixXd H_ss = H.block(s->offset, s->offset, s->tangent, s->tangent);
    const Eigen::MatrixXd inv = pseudoInverse(0.5 * (H_ss + H_ss.transpose()), eigenvalue_floor);
    std::vector<int> coupled;  // positions in `rest` where this block couples
    for (int i = 0; i < n_rest; ++i)
      if (!H.block(rest[i], s->offset, 1, s->tangent).isZero(0.0)) coupled.push_back(i);
    const int n_c = static_cast<int>(coupled.size());
    Eigen::MatrixXd H_cs(n_c, s->tangent);
    for (int i = 0; i < n_c; ++i) H_cs.row(i) = H.block(rest[coupled[i]], s->offset, 1, s->tangent);
    const Eigen::MatrixXd W = H_cs * inv;
    const Eigen::MatrixXd update = W * H_cs.transpose();
    const Eigen::VectorXd g_update = W * g.segment(s->offset, s->tangent);
    for (int j = 0; j < n_c; ++j) g_rest(coupled[j]) -= g_update(j);
    // `coupled` comes in runs of consecutive positions (a pose's six, a speed-bias' nine): subtract
    // block by block rather than through the index coefficient by coefficient (which was a third
    // of the marginalisation's time).
    std::vector<std::pair<int, int>> runs;  // (index into coupled, length)
    for (int i = 0; i < n_c; ++i) {
      if (i > 0 && coupled[i] == coupled[i - 1] + 1)
        ++runs.back().second;
      else
        runs.emplace_back(i, 1);
    }
    for (const auto& [cj, lj] : runs)
      for (const auto& [ci, li] : runs)
        H_rest.block(coupled[ci], coupled[cj], li, lj) -= update.block(ci, cj, li, lj);
  }

  const int n_kept = n_total - n_marg;
  Eigen::MatrixXd H_star = H_rest.bottomRightCorner(n_kept, n_kept);
  Eigen::VectorXd g_star = g_rest.tail(n_kept);
  if (n_dense > 0) {
    const Eigen::MatrixXd H_dd = H_rest.topLeftCorner(n_dense, n_dense);
    const Eigen::MatrixXd Hdd_inv =
        pseudoInverse(0.5 * (H_dd + H_dd.transpose()), eigenvalue_floor);
    // lazyProduct: these sizes (tens to a few hundred) do not pay for Eigen's OpenMP GEMM, whose
    // spinning threads cost more than the product on a loaded 2-core machine.
    const Eigen::MatrixXd Hkd = H_rest.bottomLeftCorner(n_kept, n_dense);
    const Eigen::MatrixXd Hkd_Hdd_inv = Hkd.lazyProduct(Hdd_inv);
    H_star -= Hkd_Hdd_inv.lazyProduct(Hkd.transpose());
    g_star -= Hkd_Hdd_inv * g_rest.head(n_dense);
  }
  H_star = 0.5 * (H_star + H_star.transpose()).eval();
  // g* is the gradient at the current values. The new prior is expanded about x0 = each kept
  // block's first estimate where it has one (else its current value), so its gradient there is
  // g* - H* (x [-] x0): exact for the quadratic the Schur complement left.
  std::vector<const double*> x0_of(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    const Block& b = kept[i];
    x0_of[i] = linearizationPoint(fej, b.address);
    if (x0_of[i] == b.address) continue;
    Eigen::VectorXd m(b.tangent);
    if (b.manifold) {
      if (!b.manifold->Minus(b.address, x0_of[i], m.data()))
        throw std::invalid_argument("Marginalizer: Minus failed");
    } else {
      for (int k = 0; k < b.size; ++k) m(k) = b.address[k] - x0_of[i][k];
    }
    g_star.noalias() -= H_star.middleCols(b.offset - n_marg, b.tangent) * m;
  }

  // H* = V S V^T. A pivoted LDLT (a fifth of the cost) was tried on 2026-11-29 and left: its
  // near-zero pivots (the gauge: position and yaw) are rounding noise of +-1e-4 that falls on
  // either side of the floor, so inputs that differ by rounding (a recorded copy of a sequence)
  // gave priors of different rank and trajectories 1 mm apart; the eigenvalues there are stable.
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
  // Information form of the same quadratic: H* and g* without the dropped eigen-directions.
  prior->H = H_star;
  prior->b = g_star;
  prior->c = prior->r.squaredNorm();
  for (int k = 0; k < n_kept; ++k) {
    if (es.eigenvalues()(k) > eigenvalue_floor) continue;
    const Eigen::VectorXd v = es.eigenvectors().col(k);
    prior->H.noalias() -= es.eigenvalues()(k) * v * v.transpose();
    prior->b -= v.dot(g_star) * v;
  }
  for (size_t i = 0; i < kept.size(); ++i) {
    const Block& b = kept[i];
    prior->blocks.push_back(b.address);
    prior->sizes.push_back(b.size);
    prior->tangent_sizes.push_back(b.tangent);
    prior->tangent_offsets.push_back(b.offset - n_marg);
    prior->manifolds.push_back(b.manifold);
    prior->x0.emplace_back(x0_of[i], x0_of[i] + b.size);
  }
  return prior;
}

Eigen::MatrixXd minusJacobianAt(const ceres::Manifold* manifold, int size, const double* x,
                                const double* x0) {
  if (!manifold) return Eigen::MatrixXd::Identity(size, size);
  if (dynamic_cast<const PoseManifold*>(manifold)) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Identity(6, 6);
    D.bottomRightCorner(3, 3) = poseMinusRotationJacobian(x, x0);
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

std::shared_ptr<const MarginalizationPrior> moveWorldFrame(
    const MarginalizationPrior& prior, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
    const std::vector<const double*>& pose_blocks,
    const std::vector<const double*>& speed_bias_blocks) {
  auto moved = std::make_shared<MarginalizationPrior>(prior);
  auto listed = [](const std::vector<const double*>& list, const double* b) {
    return std::find(list.begin(), list.end(), b) != list.end();
  };
  for (size_t k = 0; k < prior.blocks.size(); ++k) {
    const bool pose = listed(pose_blocks, prior.blocks[k]);
    if (!pose && !listed(speed_bias_blocks, prior.blocks[k])) continue;
    // Both tangents start with the world-frame vector that turns (dp of a pose, whose rotation is
    // perturbed on the right and so unchanged; dv of a speed-bias): m' = T m with T = R there.
    double* x0 = moved->x0[k].data();
    if (pose) {
      setPose(R * posePosition(x0) + t, Eigen::Quaterniond(R) * poseRotation(x0), x0);
    } else {
      Eigen::Map<Eigen::Vector3d> v0(x0);
      v0 = R * Eigen::Vector3d(v0);
    }
    // Cost c + 2 b^T m + m^T H m at m = T^T m': H' = T H T^T, b' = T b, J' = J T^T.
    const int o = prior.tangent_offsets[k];
    moved->H.middleRows(o, 3) = (R * moved->H.middleRows(o, 3)).eval();
    moved->H.middleCols(o, 3) = (moved->H.middleCols(o, 3) * R.transpose()).eval();
    moved->b.segment<3>(o) = R * moved->b.segment<3>(o);
    moved->J.middleCols(o, 3) = (moved->J.middleCols(o, 3) * R.transpose()).eval();
  }
  return moved;
}

const double* linearizationPoint(const MarginalizationPrior* prior, const double* block) {
  if (prior)
    for (size_t k = 0; k < prior->blocks.size(); ++k)
      if (prior->blocks[k] == block) return prior->x0[k].data();
  return block;
}

double informationAlongYaw(const MarginalizationPrior& prior,
                           const std::vector<const double*>& pose_blocks,
                           const std::vector<const double*>& speed_bias_blocks) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  Eigen::VectorXd n = Eigen::VectorXd::Zero(prior.tangentSize());
  for (size_t k = 0; k < prior.blocks.size(); ++k) {
    const double* x0 = prior.x0[k].data();
    const int o = prior.tangent_offsets[k];
    if (std::find(pose_blocks.begin(), pose_blocks.end(), prior.blocks[k]) != pose_blocks.end()) {
      n.segment<3>(o) = z.cross(posePosition(x0));
      n.segment<3>(o + 3) = poseRotation(x0).conjugate() * z;  // rotation perturbed on the right
    } else if (std::find(speed_bias_blocks.begin(), speed_bias_blocks.end(), prior.blocks[k]) !=
               speed_bias_blocks.end()) {
      n.segment<3>(o) = z.cross(Eigen::Vector3d(x0[0], x0[1], x0[2]));
    }
  }
  return n.dot(prior.H * n);
}

PriorLinearization linearizePrior(const MarginalizationPrior& p, const std::vector<const double*>& x,
                                  bool with_hessian, bool first_estimates) {
  const int n = p.tangentSize();
  Eigen::VectorXd m(n);
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    double* out = m.data() + p.tangent_offsets[k];
    if (p.manifolds[k]) {
      if (!p.manifolds[k]->Minus(x[k], p.x0[k].data(), out))
        throw std::invalid_argument("linearizePrior: Minus failed");
    } else {
      for (int i = 0; i < p.sizes[k]; ++i) out[i] = x[k][i] - p.x0[k][i];
    }
  }
  PriorLinearization L;
  const Eigen::VectorXd Hm = p.H * m;
  L.cost = 0.5 * (p.c + 2.0 * p.b.dot(m) + m.dot(Hm));
  L.gradient = p.b + Hm;
  if (with_hessian) L.hessian = p.H;
  if (first_estimates) return L;
  // Chain rule through Minus: only the manifold blocks have D != I.
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    if (!p.manifolds[k]) continue;
    const int o = p.tangent_offsets[k], t = p.tangent_sizes[k];
    if (dynamic_cast<const PoseManifold*>(p.manifolds[k])) {
      // D = diag(I, Jr^-1): only the three rotation rows and columns change, by a 3 x 3 product
      // each (the general path below multiplies whole 6-row blocks; it showed in the profile).
      const Eigen::Matrix3d R = poseMinusRotationJacobian(x[k], p.x0[k].data());
      const Eigen::Vector3d g_rot = L.gradient.segment<3>(o + 3);
      L.gradient.segment<3>(o + 3) = R.transpose() * g_rot;
      if (with_hessian) {
        const Eigen::MatrixXd rows = L.hessian.middleRows(o + 3, 3);
        L.hessian.middleRows(o + 3, 3).noalias() = R.transpose().lazyProduct(rows);
        const Eigen::MatrixXd cols = L.hessian.middleCols(o + 3, 3);
        L.hessian.middleCols(o + 3, 3).noalias() = cols.lazyProduct(R);
      }
      continue;
    }
    const Eigen::MatrixXd D = minusJacobianAt(p.manifolds[k], p.sizes[k], x[k], p.x0[k].data());
    L.gradient.segment(o, t) = D.transpose() * L.gradient.segment(o, t);
    if (with_hessian) {
      L.hessian.middleRows(o, t) = (D.transpose() * L.hessian.middleRows(o, t)).eval();
      L.hessian.middleCols(o, t) = (L.hessian.middleCols(o, t) * D).eval();
    }
  }
  return L;
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

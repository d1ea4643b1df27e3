#include "vio/init/visual_inertial_alignment.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "vio/imu/so3.h"
#include "vio/init/static_initializer.h"

namespace adugs::vio {
namespace {

// Rows of one pair (k, k+1) over the unknowns [v_k, v_{k+1}, g, s] (10 columns); rhs 6.
struct PairRows {
  Eigen::Matrix<double, 6, 10> A = Eigen::Matrix<double, 6, 10>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
};

PairRows pairRows(const AlignmentFrame& from, const AlignmentFrame& to,
                  const Eigen::Isometry3d& T_B_C) {
  const Eigen::Matrix3d R_BC = T_B_C.rotation();
  const Eigen::Vector3d p_BC = T_B_C.translation();
  const Eigen::Matrix3d R_k = from.R_c0_c * R_BC.transpose();  // R_c0_bk
  const Eigen::Matrix3d R_k1 = to.R_c0_c * R_BC.transpose();
  const ImuPreintegration& imu = *to.imu_from_previous;
  const double dt = imu.sumDt();
  PairRows rows;
  // alpha row: -dt v_k - R_k^T dt^2/2 g + R_k^T (pbar_{k+1} - pbar_k) s = alpha - p_BC + R_k^T
  // R_{k+1} p_BC
  rows.A.block<3, 3>(0, 0) = -dt * Eigen::Matrix3d::Identity();
  rows.A.block<3, 3>(0, 6) = -0.5 * dt * dt * R_k.transpose();
  rows.A.block<3, 1>(0, 9) = R_k.transpose() * (to.p_c0_c - from.p_c0_c);
  rows.b.head<3>() = imu.deltaP() - p_BC + R_k.transpose() * R_k1 * p_BC;
  // beta row: -v_k + R_k^T R_{k+1} v_{k+1} - R_k^T dt g = beta
  rows.A.block<3, 3>(3, 0) = -Eigen::Matrix3d::Identity();
  rows.A.block<3, 3>(3, 3) = R_k.transpose() * R_k1;
  rows.A.block<3, 3>(3, 6) = -dt * R_k.transpose();
  rows.b.tail<3>() = imu.deltaV();
  return rows;
}

bool framesUsable(const std::vector<AlignmentFrame>& frames) {
  if (frames.size() < 2) return false;
  for (size_t k = 1; k < frames.size(); ++k) {
    const auto& imu = frames[k].imu_from_previous;
    if (!imu || imu->samples().size() < 2 || imu->sumDt() <= 0) return false;
  }
  return true;
}

// Stacks all pairs into A x = b with x = [v_0..v_{n-1}, g (3), s].
void stack(const std::vector<AlignmentFrame>& frames, const Eigen::Isometry3d& T_B_C,
           Eigen::MatrixXd* A, Eigen::VectorXd* b) {
  const int n = static_cast<int>(frames.size());
  const int cols = 3 * n + 4;
  A->setZero(6 * (n - 1), cols);
  b->setZero(6 * (n - 1));
  for (int k = 0; k + 1 < n; ++k) {
    const PairRows rows = pairRows(frames[k], frames[k + 1], T_B_C);
    A->block(6 * k, 3 * k, 6, 6) = rows.A.leftCols<6>();
    A->block(6 * k, 3 * n, 6, 4) = rows.A.rightCols<4>();
    b->segment(6 * k, 6) = rows.b;
  }
}

bool unpack(const Eigen::VectorXd& x, int n, LinearAlignment* out) {
  if (!x.allFinite()) return false;
  out->velocities_body.resize(n);
  for (int k = 0; k < n; ++k) out->velocities_body[k] = x.segment<3>(3 * k);
  out->scale = x(x.size() - 1);
  return true;
}

}  // namespace

bool solveGyroBias(const std::vector<AlignmentFrame>& frames, const Eigen::Matrix3d& R_B_C,
                   Eigen::Vector3d* gyro_bias) {
  if (!framesUsable(frames)) return false;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (size_t k = 0; k + 1 < frames.size(); ++k) {
    const Eigen::Quaterniond q_k(frames[k].R_c0_c * R_B_C.transpose());
    const Eigen::Quaterniond q_k1(frames[k + 1].R_c0_c * R_B_C.transpose());
    const ImuPreintegration& imu = *frames[k + 1].imu_from_previous;
    // q_sfm ~= gamma * Exp(J (bg - bg0))  =>  J bg ~= Log(gamma^-1 q_sfm) + J bg0.
    const Eigen::Quaterniond error = imu.deltaQ().conjugate() * (q_k.conjugate() * q_k1);
    const Eigen::Matrix3d J = imu.dqDbg();
    const Eigen::Vector3d r = quaternionLog(error) + J * imu.linearizedGyroBias();
    H += J.transpose() * J;
    g += J.transpose() * r;
  }
  Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-12) return false;
  *gyro_bias = ldlt.solve(g);
  return gyro_bias->allFinite();
}

bool solveLinearAlignment(const std::vector<AlignmentFrame>& frames, const Eigen::Isometry3d& T_B_C,
                          LinearAlignment* out) {
  if (!framesUsable(frames)) return false;
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  stack(frames, T_B_C, &A, &b);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < A.cols()) return false;
  const Eigen::VectorXd x = qr.solve(b);
  if (!unpack(x, static_cast<int>(frames.size()), out)) return false;
  out->gravity_c0 = x.segment<3>(3 * frames.size());
  out->scale_std = leastSquaresStd(A, b, x, A.cols() - 1);
  return true;
}

double imuExcitation(const std::vector<AlignmentFrame>& frames) {
  std::vector<Eigen::Vector3d> mean_force;
  for (size_t k = 1; k < frames.size(); ++k) {
    const auto& imu = frames[k].imu_from_previous;
    if (imu && imu->sumDt() > 0) mean_force.push_back(imu->deltaV() / imu->sumDt());
  }
  if (mean_force.size() < 2) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& f : mean_force) mean += f;
  mean /= static_cast<double>(mean_force.size());
  Eigen::Vector3d variance = Eigen::Vector3d::Zero();
  for (const auto& f : mean_force) variance += (f - mean).cwiseAbs2();
  return (variance / static_cast<double>(mean_force.size() - 1)).cwiseSqrt().maxCoeff();
}

Eigen::VectorXd alignmentResidual(const std::vector<AlignmentFrame>& frames,
                                  const Eigen::Isometry3d& T_B_C, const LinearAlignment& solution) {
  const int n = static_cast<int>(frames.size());
  if (!framesUsable(frames) || static_cast<int>(solution.velocities_body.size()) != n) return {};
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  stack(frames, T_B_C, &A, &b);
  Eigen::VectorXd x(3 * n + 4);
  for (int k = 0; k < n; ++k) x.segment<3>(3 * k) = solution.velocities_body[k];
  x.segment<3>(3 * n) = solution.gravity_c0;
  x(3 * n + 3) = solution.scale;
  return A * x - b;
}

double leastSquaresStd(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                       Eigen::Index unknown) {
  const Eigen::Index redundancy = A.rows() - A.cols();
  if (redundancy <= 0 || unknown < 0 || unknown >= A.cols() || x.size() != A.cols()) return 0.0;
  const double sigma2 = (A * x - b).squaredNorm() / static_cast<double>(redundancy);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.transpose() * A);
  // A zero pivot: LDLT would solve with a pseudo-inverse and report a finite variance.
  const Eigen::VectorXd pivots = ldlt.vectorD().cwiseAbs();
  if (ldlt.info() != Eigen::Success || !(pivots.minCoeff() > 1e-12 * pivots.maxCoeff()))
    return std::numeric_limits<double>::infinity();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(A.cols());
  e(unknown) = 1.0;
  const double variance = sigma2 * e.dot(ldlt.solve(e));
  return std::isfinite(variance) && variance >= 0 ? std::sqrt(variance)
                                                  : std::numeric_limits<double>::infinity();
}

Eigen::Matrix<double, 3, 2> tangentBasis(const Eigen::Vector3d& g) {
  const Eigen::Vector3d a = g.normalized();
  // Any axis not parallel to a seeds the basis.
  const Eigen::Vector3d seed =
      std::abs(a.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d b1 = (seed - a * a.dot(seed)).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = b1;
  B.col(1) = a.cross(b1);
  return B;
}

bool refineGravity(const std::vector<AlignmentFrame>& frames, const Eigen::Isometry3d& T_B_C,
                   const Eigen::Vector3d& gravity_c0_guess, int iterations, LinearAlignment* out) {
  if (!framesUsable(frames) || !gravity_c0_guess.allFinite() || gravity_c0_guess.norm() < 1e-6)
    return false;
  const int n = static_cast<int>(frames.size());
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  stack(frames, T_B_C, &A, &b);
  const Eigen::MatrixXd A_g = A.middleCols(3 * n, 3);
  Eigen::Vector3d g0 = gravity_c0_guess.normalized() * kInitGravityNorm;
  for (int it = 0; it < iterations; ++it) {
    // x' = [v, w (2), s]; A_g (g0 + B w) moves g0 to the right-hand side.
    const Eigen::Matrix<double, 3, 2> B = tangentBasis(g0);
    Eigen::MatrixXd A_r(A.rows(), 3 * n + 3);
    A_r << A.leftCols(3 * n), A_g * B, A.rightCols(1);
    const Eigen::VectorXd b_r = b - A_g * g0;
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A_r);
    if (qr.rank() < A_r.cols()) return false;
    const Eigen::VectorXd x = qr.solve(b_r);
    if (!unpack(x, n, out)) return false;
    out->scale_std = leastSquaresStd(A_r, b_r, x, A_r.cols() - 1);
    g0 = (g0 + B * x.segment<2>(3 * n)).normalized() * kInitGravityNorm;
  }
  out->gravity_c0 = g0;
  return g0.allFinite();
}

Eigen::Matrix3d worldFromFirstCamera(const Eigen::Vector3d& gravity_c0,
                                     const Eigen::Matrix3d& R_c0_b0) {
  const Eigen::Matrix3d R_tilt =
      Eigen::Quaterniond::FromTwoVectors(gravity_c0, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // Remove the yaw of the first body in the tilted frame; Rz keeps gravity on -z.
  const Eigen::Matrix3d R_W_b0 = R_tilt * R_c0_b0;
  return removeYaw(R_W_b0) * R_c0_b0.transpose();
}

}  // namespace adugs::vio

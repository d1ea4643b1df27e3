#include "vio/imu/imu_preintegration.h"

#include <algorithm>
#include <iterator>

#include <Eigen/Cholesky>
#include <stdexcept>

#include "vio/imu/so3.h"

namespace adugs::vio {

ImuPreintegration::ImuPreintegration(const data::ImuSample& first,
                                     const Eigen::Vector3d& accel_bias,
                                     const Eigen::Vector3d& gyro_bias,
                                     const ImuPreintegrationOptions& options)
    : options_(options), samples_{first}, accel_bias_(accel_bias), gyro_bias_(gyro_bias) {
  reset();
}

void ImuPreintegration::reset() {
  delta_p_.setZero();
  delta_v_.setZero();
  delta_q_.setIdentity();
  jacobian_.setIdentity();
  covariance_.setZero();
}

void ImuPreintegration::integrate(const data::ImuSample& sample) {
  if (sample.t_ns <= samples_.back().t_ns)
    throw std::invalid_argument("ImuPreintegration: IMU samples must be strictly increasing");
  samples_.push_back(sample);
  step(samples_[samples_.size() - 2], samples_.back());
}

void ImuPreintegration::repropagate(const Eigen::Vector3d& accel_bias,
                                    const Eigen::Vector3d& gyro_bias) {
  accel_bias_ = accel_bias;
  gyro_bias_ = gyro_bias;
  reset();
  for (size_t k = 1; k < samples_.size(); ++k) step(samples_[k - 1], samples_[k]);
}

// One midpoint step over [a, b] and its exact linearisation F (error state) and G (noise).
void ImuPreintegration::step(const data::ImuSample& a, const data::ImuSample& b) {
  const double dt = data::nsToSec(b.t_ns - a.t_ns);
  const Eigen::Vector3d omega = 0.5 * (a.gyro + b.gyro) - gyro_bias_;
  const Eigen::Quaterniond dq_step = quaternionExp(omega * dt);
  const Eigen::Quaterniond q1 = (delta_q_ * dq_step).normalized();
  const Eigen::Matrix3d R0 = delta_q_.toRotationMatrix(), R1 = q1.toRotationMatrix();
  const Eigen::Vector3d f0 = a.accel - accel_bias_, f1 = b.accel - accel_bias_;
  const Eigen::Vector3d acc = 0.5 * (R0 * f0 + R1 * f1);

  // Linearisation at the current (pre-step) values.
  const Eigen::Matrix3d Rstep_T = dq_step.toRotationMatrix().transpose();
  const Eigen::Matrix3d Jr_dt = rightJacobian(omega * dt) * dt;
  const Eigen::Matrix3d R1f1x = R1 * skew(f1);
  const Eigen::Matrix3d dacc_dtheta = -0.5 * (R0 * skew(f0) + R1f1x * Rstep_T);
  const Eigen::Matrix3d dacc_dba = -0.5 * (R0 + R1);
  const Eigen::Matrix3d dacc_dbg = 0.5 * R1f1x * Jr_dt;
  const double h = 0.5 * dt * dt;

  // F = [A B; 0 I] on (p, q, v | ba, bg): the bias rows are the identity, so the updates are
  // done block-wise (several times faster than dense 15x15 products).
  using Matrix9d = Eigen::Matrix<double, 9, 9>;
  using Matrix96d = Eigen::Matrix<double, 9, 6>;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(kStateP, kStateQ) = h * dacc_dtheta;
  A.block<3, 3>(kStateP, kStateV) = dt * I;
  A.block<3, 3>(kStateQ, kStateQ) = Rstep_T;
  A.block<3, 3>(kStateV, kStateQ) = dt * dacc_dtheta;
  Matrix96d B = Matrix96d::Zero();  // columns ba, bg
  B.block<3, 3>(kStateP, 0) = h * dacc_dba;
  B.block<3, 3>(kStateP, 3) = h * dacc_dbg;
  B.block<3, 3>(kStateQ, 3) = -Jr_dt;
  B.block<3, 3>(kStateV, 0) = dt * dacc_dba;
  B.block<3, 3>(kStateV, 3) = dt * dacc_dbg;

  // Measurement noise (accel, gyro) enters where the bias is subtracted: G_n = -B up to the
  // rotation row (Jr dt, the sign is irrelevant for the covariance). Discrete covariances:
  // density^2 / dt for the measurement, random_walk^2 * dt for the bias steps.
  Matrix96d Gn = -B;
  Gn.block<3, 3>(kStateQ, 3) = Jr_dt;
  const double na2 = options_.accel_noise_density * options_.accel_noise_density / dt;
  const double ng2 = options_.gyro_noise_density * options_.gyro_noise_density / dt;
  const double wa2 = options_.accel_random_walk * options_.accel_random_walk * dt;
  const double wg2 = options_.gyro_random_walk * options_.gyro_random_walk * dt;
  Eigen::Matrix<double, 6, 1> noise;
  noise << na2, na2, na2, ng2, ng2, ng2;

  // Jacobian: bias rows stay [0 I]. lazyProduct: at these sizes Eigen's blocked GEMM (packing)
  // costs several times the arithmetic.
  auto J_top = jacobian_.topRows<9>();
  J_top = A.lazyProduct(J_top).eval();
  J_top.rightCols<6>() += B;
  // Covariance: P' = F P F^T + G Q G^T, block-wise.
  const Matrix9d P11 = covariance_.topLeftCorner<9, 9>();
  const Matrix96d P12 = covariance_.topRightCorner<9, 6>();
  const Eigen::Matrix<double, 6, 6> P22 = covariance_.bottomRightCorner<6, 6>();
  const Matrix96d M2 = A.lazyProduct(P12) + B.lazyProduct(P22);
  const Matrix9d M1 = A.lazyProduct(P11) + B.lazyProduct(P12.transpose());
  const Matrix96d Gn_Q = Gn * noise.asDiagonal();
  const Matrix9d P11_new = M1.lazyProduct(A.transpose()) + M2.lazyProduct(B.transpose()) +
                           Gn_Q.lazyProduct(Gn.transpose());
  covariance_.topLeftCorner<9, 9>() = 0.5 * (P11_new + P11_new.transpose());
  covariance_.topRightCorner<9, 6>() = M2;
  covariance_.bottomLeftCorner<6, 9>() = M2.transpose();
  covariance_.diagonal().segment<3>(kStateBa).array() += wa2;
  covariance_.diagonal().segment<3>(kStateBg).array() += wg2;

  delta_p_ += delta_v_ * dt + h * acc;
  delta_v_ += acc * dt;
  delta_q_ = q1;
}

Matrix15d ImuPreintegration::sqrtInformation() const {
  // One integration step (an IMU hole ending at the frame) drives delta p and delta v by the same
  // noise and leaves the covariance singular; a relative 1e-6 diagonal jitter keeps it invertible
  // and leaves regular intervals unchanged to that precision.
  Matrix15d covariance = covariance_;
  covariance.diagonal() *= 1.0 + 1e-6;
  const Matrix15d information = covariance.inverse();
  const Eigen::LLT<Matrix15d> llt(0.5 * (information + information.transpose()));
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("ImuPreintegration: covariance is not positive definite");
  return llt.matrixL().transpose();
}

ImuPreintegration::Deltas ImuPreintegration::correctedDeltas(
    const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) const {
  const Eigen::Vector3d dba = accel_bias - accel_bias_, dbg = gyro_bias - gyro_bias_;
  Deltas d;
  d.p = delta_p_ + dpDba() * dba + dpDbg() * dbg;
  d.v = delta_v_ + dvDba() * dba + dvDbg() * dbg;
  d.q = (delta_q_ * quaternionExp(dqDbg() * dbg)).normalized();
  return d;
}

Vector15d ImuPreintegration::evaluate(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                                      const Eigen::Vector3d& v_i, const Eigen::Vector3d& ba_i,
                                      const Eigen::Vector3d& bg_i, const Eigen::Vector3d& p_j,
                                      const Eigen::Quaterniond& q_j, const Eigen::Vector3d& v_j,
                                      const Eigen::Vector3d& ba_j,
                                      const Eigen::Vector3d& bg_j) const {
  const double T = sumDt();
  const Eigen::Vector3d& g = options_.gravity_W;
  const Deltas d = correctedDeltas(ba_i, bg_i);
  const Eigen::Quaterniond q_i_inv = q_i.conjugate();
  Vector15d r;
  r.segment<3>(kStateP) = q_i_inv * (p_j - p_i - v_i * T - 0.5 * g * T * T) - d.p;
  r.segment<3>(kStateQ) = 2.0 * (d.q.conjugate() * q_i_inv * q_j).vec();
  r.segment<3>(kStateV) = q_i_inv * (v_j - v_i - g * T) - d.v;
  r.segment<3>(kStateBa) = ba_j - ba_i;
  r.segment<3>(kStateBg) = bg_j - bg_i;
  return r;
}

data::ImuSample interpolateImu(const data::ImuSample& a, const data::ImuSample& b, int64_t t_ns) {
  if (t_ns < a.t_ns || t_ns > b.t_ns || b.t_ns <= a.t_ns)
    throw std::invalid_argument("interpolateImu: time outside (a, b)");
  const double s = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  data::ImuSample out;
  out.t_ns = t_ns;
  out.gyro = (1.0 - s) * a.gyro + s * b.gyro;
  out.accel = (1.0 - s) * a.accel + s * b.accel;
  return out;
}

data::ImuSample imuReadingAt(const std::deque<data::ImuSample>& samples, int64_t t_ns) {
  if (samples.empty()) throw std::invalid_argument("imuReadingAt: no IMU samples");
  // The first sample after t, and the last at or before it.
  const auto after = std::upper_bound(samples.begin(), samples.end(), t_ns,
                                      [](int64_t t, const data::ImuSample& s) { return t < s.t_ns; });
  data::ImuSample held;
  if (after == samples.begin()) held = samples.front();
  else if (after == samples.end() || std::prev(after)->t_ns == t_ns) held = *std::prev(after);
  else return interpolateImu(*std::prev(after), *after, t_ns);
  held.t_ns = t_ns;
  return held;
}

}  // namespace adugs::vio

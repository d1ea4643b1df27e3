#pragma once
// IMU preintegration between two keyframes i and j (VINS-Mono / Forster et al.), midpoint rule:
// the relative motion expressed in body frame B_i, independent of the states at i and j,
//   delta_q = q_Bi_Bj,  delta_v = R_i^T (v_j - v_i - g T),  delta_p = R_i^T (p_j - p_i - v_i T - g T^2/2),
// with first-order Jacobians w.r.t. the biases it was integrated with and a 15x15 covariance.
//
// Error state (order kP, kQ, kV, kBa, kBg): dp, dv additive; dtheta a right perturbation
// delta_q * Exp(dtheta); dba, dbg additive perturbations of the linearisation biases.
// Noise: the continuous densities of Kalibr / EuRoC sensor.yaml. Each interval of length dt gets one
// white-noise draw on the midpoint measurement with discrete covariance density^2 / dt (what an
// IMU sampled at 1/dt delivers), and the biases random-walk with covariance random_walk^2 * dt.
// (VINS-Mono instead puts density^2 on each end of the interval; see doc/estimator.md.)
#include <deque>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "data/types.h"
#include "vio/imu/imu_integrator.h"

namespace adugs::vio {

using Vector15d = Eigen::Matrix<double, 15, 1>;
using Matrix15d = Eigen::Matrix<double, 15, 15>;

// Offsets of the blocks in the 15-dim error state and residual.
constexpr int kStateP = 0, kStateQ = 3, kStateV = 6, kStateBa = 9, kStateBg = 12;

struct ImuPreintegrationOptions {
  // EuRoC ADIS16448 figures (imu0/sensor.yaml).
  double gyro_noise_density = 1.6968e-04;   // rad / s / sqrt(Hz)
  double accel_noise_density = 2.0e-3;      // m / s^2 / sqrt(Hz)
  double gyro_random_walk = 1.9393e-05;     // rad / s^2 / sqrt(Hz)
  double accel_random_walk = 3.0e-3;        // m / s^3 / sqrt(Hz)
  Eigen::Vector3d gravity_W = gravityWorld();
};

class ImuPreintegration {
 public:
  // Starts at `first` (the sample at keyframe i's time), integrating with the given biases.
  ImuPreintegration(const data::ImuSample& first, const Eigen::Vector3d& accel_bias,
                    const Eigen::Vector3d& gyro_bias, const ImuPreintegrationOptions& options = {});

  // Integrates from the last sample to `sample`. Throws std::invalid_argument if not later.
  void integrate(const data::ImuSample& sample);
  // Re-integrates every stored sample with new linearisation biases (after a large bias update).
  void repropagate(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias);

  int64_t startNs() const { return samples_.front().t_ns; }
  int64_t endNs() const { return samples_.back().t_ns; }
  double sumDt() const { return data::nsToSec(endNs() - startNs()); }
  const std::vector<data::ImuSample>& samples() const { return samples_; }
  const ImuPreintegrationOptions& options() const { return options_; }

  const Eigen::Vector3d& deltaP() const { return delta_p_; }
  const Eigen::Vector3d& deltaV() const { return delta_v_; }
  const Eigen::Quaterniond& deltaQ() const { return delta_q_; }
  const Eigen::Vector3d& linearizedAccelBias() const { return accel_bias_; }
  const Eigen::Vector3d& linearizedGyroBias() const { return gyro_bias_; }

  // d(error state at j) / d(error state at i); the bias columns are the bias Jacobians.
  const Matrix15d& jacobian() const { return jacobian_; }
  const Matrix15d& covariance() const { return covariance_; }
  // Upper-triangular S with S^T S = covariance^-1 (whitens residuals: r_white = S r): the
  // transposed Cholesky factor of the information, as VINS-Mono. Throws std::runtime_error if the
  // covariance is not positive definite (nothing integrated yet).
  Matrix15d sqrtInformation() const;

  Eigen::Matrix3d dpDba() const { return jacobian_.block<3, 3>(kStateP, kStateBa); }
  Eigen::Matrix3d dpDbg() const { return jacobian_.block<3, 3>(kStateP, kStateBg); }
  Eigen::Matrix3d dvDba() const { return jacobian_.block<3, 3>(kStateV, kStateBa); }
  Eigen::Matrix3d dvDbg() const { return jacobian_.block<3, 3>(kStateV, kStateBg); }
  Eigen::Matrix3d dqDbg() const { return jacobian_.block<3, 3>(kStateQ, kStateBg); }

  // Deltas corrected to first order for biases (accel_bias, gyro_bias) instead of the linearised
  // ones: delta_p + dp/dba dba + dp/dbg dbg, ..., delta_q * Exp(dq/dbg dbg).
  struct Deltas {
    Eigen::Vector3d p, v;
    Eigen::Quaterniond q;
  };
  Deltas correctedDeltas(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) const;

  // Residual "predicted from the states minus measured" (not whitened), order kP..kBg:
  //   r_p = R_i^T (p_j - p_i - v_i T - g T^2/2) - dp,  r_q = 2 vec(dq^-1 q_i^-1 q_j),
  //   r_v = R_i^T (v_j - v_i - g T) - dv,  r_ba = ba_j - ba_i,  r_bg = bg_j - bg_i,
  // with dp, dv, dq the deltas corrected for (ba_i, bg_i).
  Vector15d evaluate(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                     const Eigen::Vector3d& v_i, const Eigen::Vector3d& ba_i,
                     const Eigen::Vector3d& bg_i, const Eigen::Vector3d& p_j,
                     const Eigen::Quaterniond& q_j, const Eigen::Vector3d& v_j,
                     const Eigen::Vector3d& ba_j, const Eigen::Vector3d& bg_j) const;

 private:
  void reset();
  void step(const data::ImuSample& a, const data::ImuSample& b);

  ImuPreintegrationOptions options_;
  std::vector<data::ImuSample> samples_;
  Eigen::Vector3d accel_bias_, gyro_bias_;
  Eigen::Vector3d delta_p_, delta_v_;
  Eigen::Quaterniond delta_q_;
  Matrix15d jacobian_, covariance_;
};

// Linear interpolation of two samples at t_ns (a.t_ns <= t_ns <= b.t_ns), to start or end a
// preintegration exactly at a camera time.
data::ImuSample interpolateImu(const data::ImuSample& a, const data::ImuSample& b, int64_t t_ns);

// The reading at t_ns of a buffer of samples in increasing time: interpolated between the samples
// around it, the first or last held before or after the buffer (under an IMU period at a frame's
// edge). std::invalid_argument for an empty buffer.
data::ImuSample imuReadingAt(const std::deque<data::ImuSample>& samples, int64_t t_ns);

}  // namespace adugs::vio

#include "vio/estimator/imu_factor.h"

#include <stdexcept>

#include "vio/estimator/pose_manifold.h"
#include "vio/imu/so3.h"

namespace adugs::vio {

ImuFactor::ImuFactor(std::shared_ptr<const ImuPreintegration> preintegration)
    : TangentCostFunction(15, {kPoseSize, kSpeedBiasSize, kPoseSize, kSpeedBiasSize}),
      preintegration_(std::move(preintegration)) {
  if (!preintegration_ || preintegration_->samples().size() < 2)
    throw std::invalid_argument("ImuFactor: preintegration needs at least two samples");
  sqrt_information_ = preintegration_->sqrtInformation();
}

bool ImuFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  const Eigen::Vector3d p_i = posePosition(parameters[0]);
  const Eigen::Quaterniond q_i = poseRotation(parameters[0]);
  Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb_i(parameters[1]);
  const Eigen::Vector3d p_j = posePosition(parameters[2]);
  const Eigen::Quaterniond q_j = poseRotation(parameters[2]);
  Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb_j(parameters[3]);
  const Eigen::Vector3d v_i = sb_i.head<3>(), ba_i = sb_i.segment<3>(3), bg_i = sb_i.tail<3>();
  const Eigen::Vector3d v_j = sb_j.head<3>(), ba_j = sb_j.segment<3>(3), bg_j = sb_j.tail<3>();

  const ImuPreintegration& pre = *preintegration_;
  Eigen::Map<Vector15d> r(residuals);
  r = sqrt_information_ * pre.evaluate(p_i, q_i, v_i, ba_i, bg_i, p_j, q_j, v_j, ba_j, bg_j);
  if (!jacobians) return true;

  const double T = pre.sumDt();
  const Eigen::Vector3d& g = pre.options().gravity_W;
  const Eigen::Matrix3d Ri_T = q_i.toRotationMatrix().transpose();
  const Eigen::Vector3d dbg = bg_i - pre.linearizedGyroBias();
  const Eigen::Vector3d phi = pre.dqDbg() * dbg;
  const Eigen::Quaterniond dq_corr = (pre.deltaQ() * quaternionExp(phi)).normalized();
  // r_q = 2 vec(E): d/du of 2 vec(Exp(-u) E) = -(e_w I - [e_v]x), of 2 vec(E Exp(u)) = e_w I +
  // [e_v]x.
  const Eigen::Quaterniond E = dq_corr.conjugate() * q_i.conjugate() * q_j;
  const Eigen::Matrix3d A = E.w() * Eigen::Matrix3d::Identity() - skew(E.vec());
  const Eigen::Matrix3d B = E.w() * Eigen::Matrix3d::Identity() + skew(E.vec());
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();

  if (jacobians[0]) {
    Eigen::Matrix<double, 15, 6> J = Eigen::Matrix<double, 15, 6>::Zero();
    J.block<3, 3>(kStateP, 0) = -Ri_T;
    J.block<3, 3>(kStateP, 3) = skew(Ri_T * (p_j - p_i - v_i * T - 0.5 * g * T * T));
    J.block<3, 3>(kStateQ, 3) = -A * dq_corr.toRotationMatrix().transpose();
    J.block<3, 3>(kStateV, 3) = skew(Ri_T * (v_j - v_i - g * T));
    Eigen::Map<Eigen::Matrix<double, 15, 6, Eigen::RowMajor>> J_out(jacobians[0]);
    J_out = sqrt_information_ * J;
  }
  if (jacobians[1]) {
    Eigen::Matrix<double, 15, 9> J = Eigen::Matrix<double, 15, 9>::Zero();
    J.block<3, 3>(kStateP, 0) = -Ri_T * T;
    J.block<3, 3>(kStateP, 3) = -pre.dpDba();
    J.block<3, 3>(kStateP, 6) = -pre.dpDbg();
    J.block<3, 3>(kStateQ, 6) = -A * rightJacobian(phi) * pre.dqDbg();
    J.block<3, 3>(kStateV, 0) = -Ri_T;
    J.block<3, 3>(kStateV, 3) = -pre.dvDba();
    J.block<3, 3>(kStateV, 6) = -pre.dvDbg();
    J.block<3, 3>(kStateBa, 3) = -I;
    J.block<3, 3>(kStateBg, 6) = -I;
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> J_out(jacobians[1]);
    J_out = sqrt_information_ * J;
  }
  if (jacobians[2]) {
    Eigen::Matrix<double, 15, 6> J = Eigen::Matrix<double, 15, 6>::Zero();
    J.block<3, 3>(kStateP, 0) = Ri_T;
    J.block<3, 3>(kStateQ, 3) = B;
    Eigen::Map<Eigen::Matrix<double, 15, 6, Eigen::RowMajor>> J_out(jacobians[2]);
    J_out = sqrt_information_ * J;
  }
  if (jacobians[3]) {
    Eigen::Matrix<double, 15, 9> J = Eigen::Matrix<double, 15, 9>::Zero();
    J.block<3, 3>(kStateV, 0) = Ri_T;
    J.block<3, 3>(kStateBa, 3) = I;
    J.block<3, 3>(kStateBg, 6) = I;
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> J_out(jacobians[3]);
    J_out = sqrt_information_ * J;
  }
  return true;
}

}  // namespace adugs::vio

#include "data/calibration.h"

#include <Eigen/LU>
#include <cmath>

namespace adugs::data {

std::string toString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: return "none";
    case DistortionModel::kRadialTangential: break;
  }
  return "radial-tangential";
}

std::string toString(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kUnified: return "omni";
    case ProjectionModel::kDoubleSphere: return "ds";
    case ProjectionModel::kExtendedUnified: return "eucm";
    case ProjectionModel::kPinhole: break;
  }
  return "pinhole";
}

int projectionParameterCount(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kUnified: return 1;
    case ProjectionModel::kDoubleSphere:
    case ProjectionModel::kExtendedUnified: return 2;
    case ProjectionModel::kPinhole: break;
  }
  return 0;
}

}  // namespace adugs::data

namespace adugs::data {

bool ImuIntrinsics::isIdentity() const {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  return Tw == I && R_imu_gyro == I && Tg.isZero(0) && Ta == I && R_imu_acc == I;
}

void ImuIntrinsics::correct(Eigen::Vector3d& gyro, Eigen::Vector3d& accel) const {
  accel = R_imu_acc.transpose() * Ta.lu().solve(accel);
  gyro = R_imu_gyro.transpose() * Tw.lu().solve(gyro - Tg * accel);
}

void resolvePerSampleNoise(RigImu& imu, double rate_hz) {
  if (!imu.noise_per_sample) return;
  const double sqrt_dt = 1.0 / std::sqrt(rate_hz);
  ImuNoise& n = imu.noise;
  n.accel_noise_density *= sqrt_dt;
  n.gyro_noise_density *= sqrt_dt;
  n.accel_random_walk *= sqrt_dt;
  n.gyro_random_walk *= sqrt_dt;
  n.rate_hz = rate_hz;
  imu.noise_per_sample = false;
}

}  // namespace adugs::data

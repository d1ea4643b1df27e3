#pragma once
// The calibration a sequence comes with, whatever file it was read from (EuRoC sensor.yaml,
// Kalibr, a dataset preset, a live camera's defaults): the camera (intrinsics, distortion,
// camera -> body transform, rate) and the IMU's noise.
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace adugs::data {

// The lens distortion applied on the normalised image plane (after the projection below).
// kNone keeps four zero coefficients, so every camera carries the same parameter layout.
enum class DistortionModel { kRadialTangential, kEquidistant, kNone };

// How a ray reaches the normalised image plane, with the model's own parameters
// (CameraCalibration::projection_params):
//   kPinhole          (x/z, y/z)                                      none
//   kUnified          MEI / unified omnidirectional: (x, y) / (z + xi |p|)      xi
//   kDoubleSphere     Usenko et al. 2018 (Basalt "ds")                xi, alpha
//   kExtendedUnified  Khomutenko et al. 2016 (Basalt "eucm")          alpha, beta
// The pixel is (fx xd + cx, fy yd + cy) of the distorted point in every case.
enum class ProjectionModel { kPinhole, kUnified, kDoubleSphere, kExtendedUnified };

// "radial-tangential" / "equidistant" / "none" (the EuRoC spellings).
std::string toString(DistortionModel model);
// "pinhole" / "omni" / "ds" / "eucm" (Kalibr's camera_model spellings).
std::string toString(ProjectionModel model);
// How many parameters the projection has beyond fx fy cx cy (0, 1, 2, 2).
int projectionParameterCount(ProjectionModel model);

struct CameraCalibration {
  int width = 0;  // pixels
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  ProjectionModel projection = ProjectionModel::kPinhole;
  std::vector<double> projection_params;  // projectionParameterCount(projection) values, see above
  DistortionModel distortion_model = DistortionModel::kRadialTangential;
  std::vector<double> distortion;  // 4 coefficients (zeros for kNone), see above
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();  // camera -> body (EuRoC T_BS)
  double rate_hz = 0;
};

struct ImuNoise {
  double gyro_noise_density = 0;   // rad / s / sqrt(Hz)
  double gyro_random_walk = 0;     // rad / s^2 / sqrt(Hz)
  double accel_noise_density = 0;  // m / s^2 / sqrt(Hz)
  double accel_random_walk = 0;    // m / s^3 / sqrt(Hz)
  double rate_hz = 0;
  Eigen::Isometry3d T_B_I = Eigen::Isometry3d::Identity();  // IMU -> body (T_BS; optional key)
};

// The IMU's scale, misalignment and g-sensitivity: Kalibr's scale-misalignment results
// (gyroscopes M, A, C_gyro_i; accelerometers M) and OpenVINS' Tw, Tg, R_IMUtoGYRO, Ta, R_IMUtoACC,
// which name the same matrices. The measurement model (OpenVINS' propagator, Kalibr's errors):
//   w_meas = Tw R_IMUtoGYRO w + Tg a + b_g        a_meas = Ta R_IMUtoACC a + b_a
// with w, a the angular rate and specific force in the IMU frame.
struct ImuIntrinsics {
  Eigen::Matrix3d Tw = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R_imu_gyro = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d Tg = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d Ta = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R_imu_acc = Eigen::Matrix3d::Identity();

  bool isIdentity() const;
  // A raw sample -> the IMU frame: a = R_IMUtoACC^T Ta^-1 a_meas, w = R_IMUtoGYRO^T Tw^-1 (w_meas -
  // Tg a). The biases stay with the estimator, which estimates them in the corrected frame.
  void correct(Eigen::Vector3d& gyro, Eigen::Vector3d& accel) const;
};

// One camera of a rig as another tool's calibration file gives it.
struct RigCamera {
  CameraCalibration camera;  // T_B_C: camera -> IMU (the body is the IMU)
  bool has_T_imu_cam = false;
  double time_offset_s = 0;  // t_imu = t_cam + time_offset_s (Kalibr's timeshift_cam_imu, VINS' td)
  std::string rostopic;
  std::string source;  // the file it was read from
};

struct RigImu {
  ImuNoise noise;  // continuous-time densities, as Kalibr's
  // VINS-Mono/Fusion's acc_n, gyr_n, acc_w, gyr_w are the standard deviations of one sample
  // period (integration_base.h scales them by dt, not sqrt(dt)): the densities are value *
  // sqrt(dt), so they need the IMU rate (resolvePerSampleNoise).
  bool noise_per_sample = false;
  ImuIntrinsics intrinsics;
  std::string rostopic;
  std::string source;
};

// The calibration of a camera(s) + IMU rig from one or several files of any tool.
struct RigCalibration {
  std::vector<RigCamera> cameras;
  bool has_imu = false;
  RigImu imu;
  std::vector<std::string> files;
  std::vector<std::string> formats;       // what each file was recognised as, e.g. "Kalibr camchain"
  std::vector<std::string> ignored_keys;  // "FILE: key": keys that do not change the estimate
};

// Turns VINS' per-sample noise into densities at rate_hz (no-op for densities).
void resolvePerSampleNoise(RigImu& imu, double rate_hz);

}  // namespace adugs::data

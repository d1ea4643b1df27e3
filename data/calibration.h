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

}  // namespace adugs::data

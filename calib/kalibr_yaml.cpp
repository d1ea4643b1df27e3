#include "calib/kalibr_yaml.h"

#include <vector>

#include "calib/text_format.h"

namespace adugs::calib {

std::string formatCamchainYaml(const CalibCamera& c, const std::string& name,
                               const std::string& rostopic) {
  auto list = [](const std::vector<double>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i > 0 ? ", " : "") + formatDouble(v[i]);
    return s + "]";
  };
  // Kalibr's intrinsics: the projection's parameters first ([xi], [xi alpha], [alpha beta]).
  std::vector<double> intrinsics(c.projection_params.begin(),
                                 c.projection_params.begin() + data::projectionParameterCount(c.projection));
  intrinsics.insert(intrinsics.end(), c.params.begin(), c.params.begin() + 4);
  const bool none = c.model == DistortionModel::kNone;
  std::string s = name + ":\n";
  s += "  cam_overlaps: []\n";
  s += "  camera_model: " + data::toString(c.projection) + "\n";
  s += "  distortion_coeffs: " + list(none ? std::vector<double>{} : std::vector<double>(c.params.begin() + 4, c.params.end())) + "\n";
  s += "  distortion_model: " + data::kalibrName(c.model) + "\n";
  s += "  intrinsics: " + list(intrinsics) + "\n";
  s += "  resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n";
  s += "  rostopic: " + rostopic + "\n";
  return s;
}

std::string formatImuYaml(const ImuNoiseFigures& imu, const std::string& rostopic) {
  std::string s;
  s += "# IMU noise from Allan deviation (adugs calib imu); continuous-time densities.\n";
  s += "rostopic: " + rostopic + "\n";
  s += "update_rate: " + formatDouble(imu.update_rate_hz) + "  # Hz\n";
  s += "accelerometer_noise_density: " + formatDouble(imu.accel_noise_density) +
       "  # [ m / s^2 / sqrt(Hz) ]\n";
  s += "accelerometer_random_walk: " + formatDouble(imu.accel_random_walk) +
       "  # [ m / s^3 / sqrt(Hz) ]\n";
  s += "gyroscope_noise_density: " + formatDouble(imu.gyro_noise_density) +
       "  # [ rad / s / sqrt(Hz) ]\n";
  s += "gyroscope_random_walk: " + formatDouble(imu.gyro_random_walk) +
       "  # [ rad / s^2 / sqrt(Hz) ]\n";
  return s;
}

}  // namespace adugs::calib

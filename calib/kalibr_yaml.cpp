#include "calib/kalibr_yaml.h"

#include "calib/text_format.h"

namespace adugs::calib {

std::string formatCamchainYaml(const CalibCamera& c, const std::string& name,
                               const std::string& rostopic) {
  auto list = [&](int from, int to) {
    std::string s = "[";
    for (int i = from; i < to; ++i) s += (i > from ? ", " : "") + formatDouble(c.params[i]);
    return s + "]";
  };
  std::string s = name + ":\n";
  s += "  cam_overlaps: []\n";
  s += "  camera_model: pinhole\n";
  s += "  distortion_coeffs: " + list(4, 8) + "\n";
  s += "  distortion_model: " + data::kalibrName(c.model) + "\n";
  s += "  intrinsics: " + list(0, 4) + "\n";
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

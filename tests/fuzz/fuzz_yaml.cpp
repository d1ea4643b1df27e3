// libFuzzer target: arbitrary bytes as YAML, parsed as a camera sensor.yaml, an IMU sensor.yaml,
// any tool's calibration file (data/formats/calibration_files.h: Kalibr, OpenVINS, VINS, Basalt
// JSON) and an example options struct through YamlOptionsReader. Accepted sensor files must
// survive a write -> read round trip unchanged; an accepted calibration that the Kalibr writer
// can hold must read back equal.
// InputError is the expected outcome for bad input; any other exception, a crash or a sanitizer
// report is a bug.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "data/formats/calibration_files.h"
#include "data/formats/calibration_writers.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace {
using namespace adugs::data;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "BUG: %s\n", what.c_str());
  std::abort();
}

bool sameTransform(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < 1e-9;
}

void cameraRoundTrip(const std::string& text) {
  CameraCalibration c = parseEurocCameraYaml(text, "fuzz.yaml");
  CameraCalibration r = parseEurocCameraYaml(formatEurocCameraYaml(c), "written.yaml");
  if (r.width != c.width || r.height != c.height || r.fx != c.fx || r.fy != c.fy || r.cx != c.cx ||
      r.cy != c.cy || r.distortion_model != c.distortion_model || r.distortion != c.distortion ||
      r.rate_hz != c.rate_hz || !sameTransform(r.T_B_C, c.T_B_C)) {
    bug("camera sensor.yaml does not round-trip");
  }
}

void imuRoundTrip(const std::string& text) {
  ImuNoise n = parseEurocImuYaml(text, "fuzz.yaml");
  ImuNoise r = parseEurocImuYaml(formatEurocImuYaml(n), "written.yaml");
  if (r.rate_hz != n.rate_hz || r.gyro_noise_density != n.gyro_noise_density ||
      r.gyro_random_walk != n.gyro_random_walk || r.accel_noise_density != n.accel_noise_density ||
      r.accel_random_walk != n.accel_random_walk || !sameTransform(r.T_B_I, n.T_B_I)) {
    bug("IMU sensor.yaml does not round-trip");
  }
}

bool near(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::max(std::abs(a), std::abs(b))); }

void calibrationRoundTrip(const std::string& text) {
  RigCalibration rig;
  readCalibrationText(text, "fuzz.yaml", rig);
  if (rig.files.size() != rig.formats.size()) bug("calibration: files and formats differ in number");
  for (const RigCamera& c : rig.cameras)
    if (!(c.camera.fx > 0) || !(c.camera.fy > 0) || c.camera.width <= 0 || c.camera.distortion.size() != 4)
      bug("calibration: a camera without positive focal lengths, a size and 4 coefficients was accepted");
  if (rig.has_imu && rig.imu.noise_per_sample) resolvePerSampleNoise(rig.imu, 200);
  CalibrationFiles files;
  try {
    files = formatCalibration(rig, "kalibr");
  } catch (const InputError&) {
    return;  // what Kalibr's files cannot hold
  }
  RigCalibration back;
  for (const auto& [name, body] : files) readCalibrationText(body, name, back);
  if (back.cameras.size() != rig.cameras.size()) bug("calibration: camera count does not round-trip");
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const CameraCalibration &a = rig.cameras[i].camera, &b = back.cameras[i].camera;
    if (a.fx != b.fx || a.fy != b.fy || a.cx != b.cx || a.cy != b.cy || a.width != b.width ||
        a.projection != b.projection || a.projection_params != b.projection_params ||
        a.distortion_model != b.distortion_model || a.distortion != b.distortion)
      bug("calibration: camera " + std::to_string(i) + " does not round-trip");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        if (!near(a.T_B_C(r, c), b.T_B_C(r, c))) bug("calibration: T_imu_cam does not round-trip");
  }
  if (back.imu.noise.accel_noise_density != rig.imu.noise.accel_noise_density ||
      back.imu.noise.gyro_random_walk != rig.imu.noise.gyro_random_walk)
    bug("calibration: IMU noise does not round-trip");
}

void exampleOptions(const std::string& text) {
  int max_features = 150;
  double quality = 0.01;
  bool use_klt = true;
  float score = 0.5f;
  int64_t t_ns = 0;
  std::string name;
  std::vector<double> weights;
  std::vector<int> sizes;
  std::vector<std::string> labels;
  int erode_px = 3;
  YamlOptionsReader r = YamlOptionsReader::fromString(text, "options.yaml");
  r.optional("max_features", max_features, 1, 5000);
  r.optional("quality", quality, 0.0, 1.0);
  r.optional("use_klt", use_klt);
  r.optional("score", score);
  r.optional("t_ns", t_ns);
  r.optional("name", name);
  r.optional("weights", weights);
  r.optional("sizes", sizes);
  YamlOptionsReader m = r.child("masker");
  m.optional("erode_px", erode_px, 0, 50);
  m.optional("labels", labels);
  m.finish();
  r.finish();
  if (!std::isfinite(quality) || max_features < 1) bug("range check let a bad value through");
}

template <typename F>
void expectOnlyInputError(const char* what, F&& f) {
  try {
    f();
  } catch (const InputError&) {
    // expected for bad input
  } catch (const std::exception& e) {
    bug(std::string(what) + " threw a non-InputError exception: " + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  expectOnlyInputError("camera sensor.yaml", [&] { cameraRoundTrip(text); });
  expectOnlyInputError("IMU sensor.yaml", [&] { imuRoundTrip(text); });
  expectOnlyInputError("YamlOptionsReader", [&] { exampleOptions(text); });
  expectOnlyInputError("calibration files", [&] { calibrationRoundTrip(text); });
  return 0;
}

// libFuzzer target: arbitrary bytes as YAML, parsed as a camera sensor.yaml, an IMU sensor.yaml
// and an example options struct through YamlOptionsReader. Accepted sensor files must survive a
// write -> read round trip unchanged.
// InputError is the expected outcome for bad input; any other exception, a crash or a sanitizer
// report is a bug.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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
  return 0;
}

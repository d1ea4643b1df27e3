#include "data/formats/kalibr_calibration.h"

#include <vector>

#include "data/camera_model.h"
#include "data/formats/yaml_options.h"
#include "data/types.h"

namespace adugs::data {
namespace {

Eigen::Isometry3d readMatrix(YamlOptionsReader& r, const std::string& key) {
  std::vector<std::vector<double>> rows;
  r.required(key, rows);
  bool square = rows.size() == 4;
  for (const auto& row : rows) square = square && row.size() == 4;
  r.check(square, key, "expected a 4x4 matrix as 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = rows[i][j];
  return rigidTransform(r, key, m);
}

KalibrCamera parseCamera(YamlOptionsReader root, const std::string& name) {
  YamlOptionsReader r = root.child(name, true);
  KalibrCamera out = readKalibrCameraMap(r);
  // Other cameras of the chain (cam1...) are allowed and ignored; anything else is an error.
  for (int i = 0; i < 16; ++i) {
    const std::string other = "cam" + std::to_string(i);
    if (other != name && root.has(other)) root.child(other);
  }
  root.finish();
  return out;
}

KalibrImu parseImu(YamlOptionsReader root) {
  YamlOptionsReader r = root.child("imu0", true);
  KalibrImu out = readKalibrImuMap(r);
  root.finish();
  return out;
}

}  // namespace

KalibrCamera readKalibrCameraMap(YamlOptionsReader& r) {
  KalibrCamera out;
  CameraCalibration& cam = out.camera;
  readPinholeIntrinsics(r, &cam);

  std::string dist;
  r.required("distortion_model", dist);
  r.check(parseDistortionModel(dist, cam.distortion_model), "distortion_model",
          "expected 'radtan' or 'equidistant', found '" + dist + "'");
  r.required("distortion_coeffs", cam.distortion);
  r.check(cam.distortion.size() == 4, "distortion_coeffs",
          "expected 4 coefficients, found " + std::to_string(cam.distortion.size()));

  std::vector<int> resolution;
  r.required("resolution", resolution);
  r.check(resolution.size() == 2 && resolution[0] > 0 && resolution[1] > 0, "resolution",
          "expected [width, height], both positive");
  cam.width = resolution[0];
  cam.height = resolution[1];

  if (r.has("T_cam_imu")) {
    cam.T_B_C = readMatrix(r, "T_cam_imu").inverse();
    out.has_T_cam_imu = true;
  }
  double shift_s = 0;
  r.optional("timeshift_cam_imu", shift_s, -1.0, 1.0);
  out.time_shift_ns = secToNs(shift_s);
  r.optional("rostopic", out.rostopic);
  // Kalibr writes these too; they do not concern a single camera.
  std::vector<int> overlaps;
  r.optional("cam_overlaps", overlaps);
  if (r.has("T_cn_cnm1")) readMatrix(r, "T_cn_cnm1");
  r.optional("rate_hz", cam.rate_hz, 0.0, 1e4);
  r.finish();
  return out;
}

KalibrImu readKalibrImuMap(YamlOptionsReader& r) {
  KalibrImu out;
  ImuNoise& n = out.noise;
  r.required("accelerometer_noise_density", n.accel_noise_density, 1e-12, 1e3);
  r.required("accelerometer_random_walk", n.accel_random_walk, 1e-12, 1e3);
  r.required("gyroscope_noise_density", n.gyro_noise_density, 1e-12, 1e3);
  r.required("gyroscope_random_walk", n.gyro_random_walk, 1e-12, 1e3);
  r.optional("update_rate", n.rate_hz, 1.0, 1e5);
  r.optional("rostopic", out.rostopic);
  std::string model;
  r.optional("model", model);
  double time_offset = 0;
  r.optional("time_offset", time_offset);
  if (r.has("T_i_b")) n.T_B_I = readMatrix(r, "T_i_b").inverse();
  r.finish();
  return out;
}

KalibrCamera parseKalibrCamchain(const std::string& text, const std::string& source, const std::string& camera) {
  return parseCamera(YamlOptionsReader::fromString(text, source), camera);
}
KalibrCamera readKalibrCamchain(const std::string& path, const std::string& camera) {
  return parseCamera(YamlOptionsReader::fromFile(path), camera);
}
KalibrImu parseKalibrImu(const std::string& text, const std::string& source) {
  return parseImu(YamlOptionsReader::fromString(text, source));
}
KalibrImu readKalibrImu(const std::string& path) { return parseImu(YamlOptionsReader::fromFile(path)); }

}  // namespace adugs::data

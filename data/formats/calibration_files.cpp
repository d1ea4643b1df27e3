#include "data/formats/calibration_files.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "data/formats/basalt_calibration.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/kalibr_calibration.h"
#include "data/formats/vins_calibration.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {

bool near(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::max(std::abs(a), std::abs(b))); }

bool sameVector(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!near(a[i], b[i])) return false;
  return true;
}

bool sameTransform(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() <= 1e-9;
}

// What differs between two readings of one camera ("" when they agree).
std::string cameraDifference(const CameraCalibration& a, const CameraCalibration& b) {
  if (a.projection != b.projection || !sameVector(a.projection_params, b.projection_params)) return "camera model";
  if (!near(a.fx, b.fx) || !near(a.fy, b.fy) || !near(a.cx, b.cx) || !near(a.cy, b.cy)) return "intrinsics";
  if (a.distortion_model != b.distortion_model || !sameVector(a.distortion, b.distortion)) return "distortion";
  if (a.width != b.width || a.height != b.height) return "resolution";
  return "";
}

std::string noiseDifference(const RigImu& a, const RigImu& b) {
  const ImuNoise &x = a.noise, &y = b.noise;
  if (a.noise_per_sample != b.noise_per_sample || !near(x.accel_noise_density, y.accel_noise_density) ||
      !near(x.accel_random_walk, y.accel_random_walk) || !near(x.gyro_noise_density, y.gyro_noise_density) ||
      !near(x.gyro_random_walk, y.gyro_random_walk))
    return "noise figures";
  if (x.rate_hz > 0 && y.rate_hz > 0 && !near(x.rate_hz, y.rate_hz)) return "update rate";
  if (!sameTransform(x.T_B_I, y.T_B_I)) return "T_i_b";
  return "";
}

// Adds what one file holds to what the earlier files held; they must agree where both speak.
void merge(RigCalibration& rig, RigCalibration&& file) {
  for (size_t i = 0; i < file.cameras.size(); ++i) {
    RigCamera& cam = file.cameras[i];
    if (i >= rig.cameras.size()) {
      rig.cameras.push_back(std::move(cam));
      continue;
    }
    RigCamera& have = rig.cameras[i];
    const std::string field = "cam" + std::to_string(i);
    const std::string diff = cameraDifference(have.camera, cam.camera);
    if (!diff.empty())
      throw InputError(cam.source, 0, field, "its " + diff + " differ from " + have.source + "'s: give one of the two files");
    if (have.has_T_imu_cam && cam.has_T_imu_cam && !sameTransform(have.camera.T_B_C, cam.camera.T_B_C))
      throw InputError(cam.source, 0, field + ".T_cam_imu", "differs from the camera-IMU transform of " + have.source);
    if (!have.has_T_imu_cam && cam.has_T_imu_cam) {
      have.camera.T_B_C = cam.camera.T_B_C;
      have.has_T_imu_cam = true;
    }
    if (cam.time_offset_s != 0 && have.time_offset_s != 0 && !near(cam.time_offset_s, have.time_offset_s))
      throw InputError(cam.source, 0, field + ".timeshift_cam_imu", "differs from the time offset of " + have.source);
    if (have.time_offset_s == 0) have.time_offset_s = cam.time_offset_s;
    if (have.rostopic.empty()) have.rostopic = cam.rostopic;
    if (have.camera.rate_hz == 0) have.camera.rate_hz = cam.camera.rate_hz;
  }
  if (file.has_imu) {
    if (rig.has_imu) {
      const std::string diff = noiseDifference(rig.imu, file.imu);
      if (!diff.empty())
        throw InputError(file.imu.source, 0, "imu", "its " + diff + " differ from " + rig.imu.source + "'s: give one of the two files");
      if (rig.imu.noise.rate_hz == 0) rig.imu.noise.rate_hz = file.imu.noise.rate_hz;
    } else {
      rig.imu = std::move(file.imu);
      rig.has_imu = true;
    }
  }
  rig.files.insert(rig.files.end(), file.files.begin(), file.files.end());
  rig.formats.insert(rig.formats.end(), file.formats.begin(), file.formats.end());
  rig.ignored_keys.insert(rig.ignored_keys.end(), file.ignored_keys.begin(), file.ignored_keys.end());
}

std::string topKeys(const YAML::Node& node) {
  std::string keys;
  if (node.IsMap())
    for (const auto& kv : node) keys += (keys.empty() ? "" : ", ") + kv.first.as<std::string>("?");
  return keys.empty() ? "none" : keys;
}

// One file, recognised by its keys.
RigCalibration readOne(const YAML::Node& node, const std::string& source, const std::string& path) {
  RigCalibration rig;
  if (!node.IsMap()) throw InputError(source, 1, "", "expected a YAML or JSON map of calibration keys");
  YamlOptionsReader r(node, source);
  std::string format;
  if (r.has("sensor_type")) {  // EuRoC/ASL before Kalibr: its IMU file has Kalibr's key names
    std::string type;
    YamlOptionsReader(node, source).optional("sensor_type", type);
    std::ostringstream text;
    text << node;
    if (type == "camera") {
      format = "EuRoC camera sensor.yaml";
      RigCamera cam;
      cam.source = source;
      cam.camera = path.empty() ? parseEurocCameraYaml(text.str(), source) : readEurocCameraYaml(path);
      cam.has_T_imu_cam = true;
      rig.cameras.push_back(cam);
    } else if (type == "imu") {
      format = "EuRoC imu sensor.yaml";
      rig.has_imu = true;
      rig.imu.source = source;
      rig.imu.noise = path.empty() ? parseEurocImuYaml(text.str(), source) : readEurocImuYaml(path);
    } else {
      r.fail("sensor_type", "expected camera or imu, found '" + type + "'");
    }
  } else if (isBasaltFile(r)) {
    format = "Basalt calibration JSON";
    readBasaltFile(r, rig);
  } else if (isVinsFile(r)) {
    format = r.has("cam0_calib") || r.has("acc_n") ? "VINS config" : "VINS camera";
    readVinsFile(r, path, rig);
  } else if (r.has("cam0")) {
    format = "Kalibr camchain";
    readKalibrCamchain(r, rig);
  } else if (r.has("imu0") || r.has("accelerometer_noise_density")) {
    format = r.has("imu0") ? "Kalibr imu" : "Kalibr imu (flat)";
    readKalibrImu(r, rig);
  } else {
    throw InputError(source, 1, "",
                     "not a calibration file adugs reads (Kalibr camchain or imu, OpenVINS kalibr_*.yaml, "
                     "VINS-Mono/Fusion config or camera file, Basalt calibration JSON, EuRoC sensor.yaml); "
                     "its top-level keys: " + topKeys(node));
  }
  rig.files.insert(rig.files.begin(), source);
  rig.formats.insert(rig.formats.begin(), format);
  return rig;
}

}  // namespace

void readCalibrationText(const std::string& text, const std::string& source, RigCalibration& rig) {
  merge(rig, readOne(loadYamlString(text, source), source, ""));
}

void reportIgnoredKeys(const RigCalibration& rig, std::ostream& out) {
  std::string file, keys;
  auto flush = [&] {
    if (!keys.empty()) out << "note: " << file << ": ignored (no effect on the estimate): " << keys << "\n";
    keys.clear();
  };
  for (const std::string& entry : rig.ignored_keys) {
    const size_t colon = entry.find(": ");
    const std::string f = entry.substr(0, colon), key = entry.substr(colon + 2);
    if (f != file) {
      flush();
      file = f;
    }
    keys += (keys.empty() ? "" : ", ") + key;
  }
  flush();
}

RigCalibration readCalibrationFiles(const std::vector<std::string>& paths) {
  RigCalibration rig;
  for (const std::string& path : paths) merge(rig, readOne(loadYamlFile(path), path, path));
  return rig;
}

}  // namespace adugs::data

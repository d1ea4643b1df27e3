#include "calib/camera_imu/camera_imu_input.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "data/formats/calibration_files.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace {

using data::InputError;

long lineOf(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

YAML::Node need(const YAML::Node& parent, const std::string& key, const std::string& path,
                const std::string& where) {
  if (!parent.IsMap()) throw InputError(path, lineOf(parent), where, "expected a map");
  YAML::Node n = parent[key];
  if (!n) throw InputError(path, lineOf(parent), where + key, "missing");
  return n;
}

double number(const YAML::Node& n, const std::string& path, const std::string& field) {
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(path, lineOf(n), field, "expected a number");
  }
  if (!std::isfinite(v)) throw InputError(path, lineOf(n), field, "must be finite");
  return v;
}

std::vector<double> numbers(const YAML::Node& n, size_t count, const std::string& path,
                            const std::string& field) {
  if (!n.IsSequence() || n.size() != count)
    throw InputError(path, lineOf(n), field,
                     "expected a list of " + std::to_string(count) + " numbers");
  std::vector<double> v;
  for (const auto& e : n) v.push_back(number(e, path, field));
  return v;
}

void checkCamera(const CalibCamera& c, const std::string& path, const std::string& field) {
  if (c.width <= 0 || c.height <= 0)
    throw InputError(path, 0, field + "resolution", "must be positive");
  if (!(c.params[0] > 0 && c.params[1] > 0))
    throw InputError(path, 0, field + "intrinsics", "focal lengths must be positive");
}

CalibCamera readCamera(const YAML::Node& cam, const std::string& path, const std::string& prefix,
                         const char* intrinsics_key, const char* coeffs_key,
                         const char* model_key) {
  CalibCamera c;
  const auto res = numbers(need(cam, "resolution", path, prefix), 2, path, prefix + "resolution");
  c.width = static_cast<int>(res[0]);
  c.height = static_cast<int>(res[1]);
  const auto k = numbers(need(cam, intrinsics_key, path, prefix), 4, path, prefix + intrinsics_key);
  const auto d = numbers(need(cam, coeffs_key, path, prefix), 4, path, prefix + coeffs_key);
  const YAML::Node model = need(cam, model_key, path, prefix);
  if (!data::parseDistortionModel(model.as<std::string>(""), c.model))
    throw InputError(path, lineOf(model), prefix + model_key,
                     "unknown distortion model '" + model.as<std::string>("") + "'");
  if (YAML::Node proj = cam["camera_model"] ? cam["camera_model"] : cam["proj_model"]) {
    if (proj.as<std::string>("") != "pinhole")
      throw InputError(path, lineOf(proj), prefix + "camera_model", "only pinhole is supported");
  }
  for (int i = 0; i < 4; ++i) {
    c.params[i] = k[i];
    c.params[4 + i] = d[i];
  }
  checkCamera(c, path, prefix);
  return c;
}

}  // namespace

CameraImuSensors readYacCalibConfig(const std::string& path, const std::string& camera_name) {
  const YAML::Node root = data::loadYamlFile(path);
  CameraImuSensors s;
  if (YAML::Node cam = root[camera_name]) {
    s.camera = readCamera(cam, path, camera_name + ".", "proj_params", "dist_params", "dist_model");
    s.has_camera = true;
  }
  if (YAML::Node imu = root["imu0"]) {
    auto field = [&](const char* key) {
      return number(need(imu, key, path, "imu0."), path, std::string("imu0.") + key);
    };
    s.imu.update_rate_hz = field("rate");
    s.imu.accel_noise_density = field("sigma_a_c");
    s.imu.gyro_noise_density = field("sigma_g_c");
    s.imu.accel_random_walk = field("sigma_aw_c");
    s.imu.gyro_random_walk = field("sigma_gw_c");
    if (imu["g"]) s.gravity = field("g");
    if (!(s.imu.accel_noise_density > 0 && s.imu.gyro_noise_density > 0 &&
          s.imu.update_rate_hz > 0))
      throw InputError(path, lineOf(imu), "imu0", "noise densities and rate must be positive");
    if (!(s.gravity > 9 && s.gravity < 10.5))
      throw InputError(path, lineOf(imu), "imu0.g", "must be about 9.81");
    s.has_imu = true;
  }
  if (!s.has_camera && !s.has_imu)
    throw InputError(path, 0, camera_name, "neither '" + camera_name + "' nor 'imu0' found");
  return s;
}

// Both through the one reader of calibration files (data/formats/calibration_files.h), so any
// tool's file works here as it does for `adugs run`.
CalibCamera readKalibrCamchain(const std::string& path, const std::string& camera_name) {
  const data::RigCalibration rig = data::readCalibrationFiles({path});
  size_t index = 0;
  if (camera_name.rfind("cam", 0) != 0 || std::sscanf(camera_name.c_str() + 3, "%zu", &index) != 1)
    throw InputError(path, 0, camera_name, "expected a camera name cam0, cam1, ...");
  if (index >= rig.cameras.size()) throw InputError(path, 0, camera_name, "missing: the file has " + std::to_string(rig.cameras.size()) + " camera(s)");
  const data::CameraCalibration& c = rig.cameras[index].camera;
  if (c.projection != data::ProjectionModel::kPinhole)
    throw InputError(path, 0, camera_name + ".camera_model",
                     "the calibration takes pinhole cameras (radtan, equidistant or no distortion), found " +
                         data::toString(c.projection));
  CalibCamera p;
  p.width = c.width;
  p.height = c.height;
  p.model = c.distortion_model == data::DistortionModel::kNone ? data::DistortionModel::kRadialTangential
                                                               : c.distortion_model;
  p.params = {c.fx, c.fy, c.cx, c.cy, c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3]};
  return p;
}

ImuNoiseFigures readKalibrImuYaml(const std::string& path) {
  const data::RigCalibration rig = data::readCalibrationFiles({path});
  if (!rig.has_imu) throw InputError(path, 0, "imu0", "no IMU noise figures in this file");
  if (rig.imu.noise_per_sample)
    throw InputError(path, 0, "acc_n", "VINS' per-sample noise figures need the IMU rate: give a Kalibr imu.yaml");
  const data::ImuNoise& n = rig.imu.noise;
  if (!(n.rate_hz > 0)) throw InputError(path, 0, "update_rate", "missing: the calibration needs the IMU rate");
  ImuNoiseFigures f;
  f.accel_noise_density = n.accel_noise_density;
  f.accel_random_walk = n.accel_random_walk;
  f.gyro_noise_density = n.gyro_noise_density;
  f.gyro_random_walk = n.gyro_random_walk;
  f.update_rate_hz = n.rate_hz;
  return f;
}

Eigen::Isometry3d readEurocCameraToImu(const std::string& path) {
  return data::readEurocCameraYaml(path).T_B_C;
}

}  // namespace adugs::calib

#include "data/formats/vins_calibration.h"

#include <filesystem>
#include <vector>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/yaml_options.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

// An OpenCV !!opencv-matrix map: rows, cols, dt, data (row-major).
Eigen::MatrixXd readOpenCvMatrix(YamlOptionsReader& parent, const std::string& key, int rows, int cols) {
  YamlOptionsReader m = parent.child(key, true);
  int r = 0, c = 0;
  std::string dt;
  std::vector<double> data;
  m.required("rows", r);
  m.required("cols", c);
  m.optional("dt", dt);
  m.required("data", data);
  m.check(r == rows && c == cols, "rows",
          "expected a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix, found " +
              std::to_string(r) + "x" + std::to_string(c));
  m.check(static_cast<int>(data.size()) == rows * cols, "data",
          "expected " + std::to_string(rows * cols) + " numbers, found " + std::to_string(data.size()));
  m.finish();
  Eigen::MatrixXd out(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) out(i, j) = data[static_cast<size_t>(i * cols + j)];
  return out;
}

double requiredPositive(YamlOptionsReader& r, const std::string& key) {
  double v = 0;
  r.required(key, v);
  r.check(v > 0, key, "must be positive");
  return v;
}

// The camera keys of a camera file, or of a VINS-Mono config.
CameraCalibration readCamera(YamlOptionsReader& r) {
  CameraCalibration cam;
  std::string model;
  r.required("model_type", model);
  r.required("image_width", cam.width, 1, 100000);
  r.required("image_height", cam.height, 1, 100000);
  YamlOptionsReader proj = r.child("projection_parameters", true);
  auto radtan = [&](YamlOptionsReader& d) {
    cam.distortion_model = DistortionModel::kRadialTangential;
    cam.distortion.assign(4, 0.0);
    d.required("k1", cam.distortion[0]);
    d.required("k2", cam.distortion[1]);
    d.required("p1", cam.distortion[2]);
    d.required("p2", cam.distortion[3]);
    d.finish();
  };
  if (model == "PINHOLE") {
    YamlOptionsReader d = r.child("distortion_parameters", true);
    radtan(d);
    cam.fx = requiredPositive(proj, "fx");
    cam.fy = requiredPositive(proj, "fy");
    proj.required("cx", cam.cx);
    proj.required("cy", cam.cy);
  } else if (model == "MEI") {
    cam.projection = ProjectionModel::kUnified;
    YamlOptionsReader mirror = r.child("mirror_parameters", true);
    cam.projection_params.assign(1, 0.0);
    mirror.required("xi", cam.projection_params[0]);
    mirror.finish();
    YamlOptionsReader d = r.child("distortion_parameters", true);
    radtan(d);
    cam.fx = requiredPositive(proj, "gamma1");
    cam.fy = requiredPositive(proj, "gamma2");
    proj.required("u0", cam.cx);
    proj.required("v0", cam.cy);
  } else if (model == "KANNALA_BRANDT") {
    cam.distortion_model = DistortionModel::kEquidistant;
    cam.distortion.assign(4, 0.0);
    proj.required("k2", cam.distortion[0]);
    proj.required("k3", cam.distortion[1]);
    proj.required("k4", cam.distortion[2]);
    proj.required("k5", cam.distortion[3]);
    cam.fx = requiredPositive(proj, "mu");
    cam.fy = requiredPositive(proj, "mv");
    proj.required("u0", cam.cx);
    proj.required("v0", cam.cy);
  } else {
    r.fail("model_type", "expected PINHOLE, MEI or KANNALA_BRANDT, found '" + model + "'");
  }
  proj.finish();
  try {
    CameraModel check(cam);
  } catch (const std::invalid_argument& e) {
    r.fail("projection_parameters", e.what());
  }
  return cam;
}

void collectIgnored(const YamlOptionsReader& r, RigCalibration& rig) {
  for (const std::string& key : r.unusedKeys()) rig.ignored_keys.push_back(r.source() + ": " + key);
}

}  // namespace

bool isVinsFile(const YamlOptionsReader& r) {
  return r.has("model_type") || r.has("cam0_calib") || r.has("body_T_cam0") || r.has("acc_n") ||
         r.has("extrinsicRotation");
}

void readVinsFile(YamlOptionsReader r, const std::string& path, RigCalibration& rig) {
  if (!r.has("cam0_calib") && !r.has("acc_n")) {  // a lone camera file
    RigCamera cam;
    cam.source = path;
    cam.camera = readCamera(r);
    rig.cameras.push_back(cam);
    std::string name;
    r.optional("camera_name", name);
    collectIgnored(r, rig);
    return;
  }
  double td = 0;
  r.optional("td", td, -1.0, 1.0);
  int num_cam = 1;
  if (r.has("cam0_calib")) {  // VINS-Fusion: camera files beside the config
    r.optional("num_of_cam", num_cam, 1, 2);
    int width = 0, height = 0;
    r.optional("image_width", width);
    r.optional("image_height", height);
    for (int i = 0; i < num_cam; ++i) {
      const std::string key = "cam" + std::to_string(i) + "_calib";
      std::string file;
      r.required(key, file);
      // Text without a file (a preset, the fuzzer) has no folder to find camera files in.
      r.check(!path.empty(), key, "a configuration given as text cannot name camera files");
      const std::string camera_path = (fs::path(path).parent_path() / file).string();
      RigCamera cam;
      cam.source = camera_path;
      YamlOptionsReader cr = YamlOptionsReader::fromFile(camera_path);
      cam.camera = readCamera(cr);
      std::string name;
      cr.optional("camera_name", name);
      collectIgnored(cr, rig);
      rig.files.push_back(camera_path);
      rig.formats.push_back("VINS camera (named by " + path + ")");
      // VINS-Fusion's own KITTI configs give a size the camera files do not: the camera file's
      // is the calibration's, the config's only bounds the feature tracker.
      if (width != 0 && (width != cam.camera.width || height != cam.camera.height))
        rig.ignored_keys.push_back(path + ": image_width/image_height (" + std::to_string(width) + "x" +
                                   std::to_string(height) + "; the camera file's " + std::to_string(cam.camera.width) +
                                   "x" + std::to_string(cam.camera.height) + " is used)");
      const std::string ext = "body_T_cam" + std::to_string(i);
      if (r.has(ext)) {
        cam.camera.T_B_C = rigidTransform(r, ext, readOpenCvMatrix(r, ext, 4, 4), kForeignRigidTolerance);
        cam.has_T_imu_cam = true;
      }
      cam.time_offset_s = td;
      r.optional("image" + std::to_string(i) + "_topic", cam.rostopic);
      rig.cameras.push_back(cam);
    }
  } else if (r.has("model_type")) {  // VINS-Mono: one camera in the config
    RigCamera cam;
    cam.source = path;
    cam.camera = readCamera(r);
    std::string name;
    r.optional("camera_name", name);
    int estimate = 0;
    r.optional("estimate_extrinsic", estimate, 0, 2);
    if (r.has("extrinsicRotation") && estimate != 2) {
      Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
      m.topLeftCorner<3, 3>() = readOpenCvMatrix(r, "extrinsicRotation", 3, 3);
      m.topRightCorner<3, 1>() = readOpenCvMatrix(r, "extrinsicTranslation", 3, 1);
      cam.camera.T_B_C = rigidTransform(r, "extrinsicRotation", m, kForeignRigidTolerance);
      cam.has_T_imu_cam = true;
    }
    cam.time_offset_s = td;
    r.optional("image_topic", cam.rostopic);
    rig.cameras.push_back(cam);
  }
  int use_imu = 1;
  r.optional("imu", use_imu, 0, 1);
  if (use_imu && r.has("acc_n")) {
    rig.has_imu = true;
    RigImu& imu = rig.imu;
    imu = RigImu{};
    imu.source = path;
    imu.noise_per_sample = true;
    r.required("acc_n", imu.noise.accel_noise_density, 1e-12, 1e3);
    r.required("gyr_n", imu.noise.gyro_noise_density, 1e-12, 1e3);
    r.required("acc_w", imu.noise.accel_random_walk, 1e-12, 1e3);
    r.required("gyr_w", imu.noise.gyro_random_walk, 1e-12, 1e3);
    r.optional("imu_topic", imu.rostopic);
  }
  collectIgnored(r, rig);
}

}  // namespace adugs::data

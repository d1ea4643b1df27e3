#include "data/formats/basalt_calibration.h"

#include <algorithm>
#include <vector>

#include <Eigen/Geometry>

#include "data/camera_model.h"
#include "data/formats/yaml_options.h"

namespace adugs::data {
namespace {

void collectIgnored(const YamlOptionsReader& r, RigCalibration& rig) {
  for (const std::string& key : r.unusedKeys()) rig.ignored_keys.push_back(r.source() + ": " + key);
}

// The list under key as one reader per element (cereal writes lists of maps).
std::vector<YamlOptionsReader> mapList(YamlOptionsReader& r, const std::string& key) {
  std::vector<YamlOptionsReader> out;
  YAML::Node list = r.node(key);
  if (!list.IsDefined()) return out;
  r.check(list.IsSequence(), key, "expected a list");
  for (size_t i = 0; i < list.size(); ++i) {
    YAML::Node item = list[i];
    if (!item.IsMap()) r.fail(key, "element " + std::to_string(i) + " is not a map");
    out.emplace_back(item, r.source(), key + "[" + std::to_string(i) + "].");
  }
  return out;
}

Eigen::Isometry3d readPose(YamlOptionsReader& p) {
  double px, py, pz, qx, qy, qz, qw;
  p.required("px", px);
  p.required("py", py);
  p.required("pz", pz);
  p.required("qx", qx);
  p.required("qy", qy);
  p.required("qz", qz);
  p.required("qw", qw);
  Eigen::Quaterniond q(qw, qx, qy, qz);
  p.check(std::abs(q.norm() - 1) < 1e-3, "qw", "the quaternion is not of unit length");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(px, py, pz);
  p.finish();
  return T;
}

CameraCalibration readIntrinsics(YamlOptionsReader& c) {
  CameraCalibration cam;
  std::string type;
  c.required("camera_type", type);
  YamlOptionsReader k = c.child("intrinsics", true);
  cam.distortion_model = DistortionModel::kNone;
  cam.distortion.assign(4, 0.0);
  k.required("fx", cam.fx);
  k.required("fy", cam.fy);
  k.required("cx", cam.cx);
  k.required("cy", cam.cy);
  k.check(cam.fx > 0 && cam.fy > 0, "fx", "focal lengths must be positive");
  if (type == "pinhole") {
  } else if (type == "kb4") {
    cam.distortion_model = DistortionModel::kEquidistant;
    k.required("k1", cam.distortion[0]);
    k.required("k2", cam.distortion[1]);
    k.required("k3", cam.distortion[2]);
    k.required("k4", cam.distortion[3]);
  } else if (type == "ds") {
    cam.projection = ProjectionModel::kDoubleSphere;
    cam.projection_params.assign(2, 0.0);
    k.required("xi", cam.projection_params[0]);
    k.required("alpha", cam.projection_params[1]);
  } else if (type == "eucm" || type == "unified") {
    cam.projection = ProjectionModel::kExtendedUnified;
    cam.projection_params.assign(2, 1.0);
    k.required("alpha", cam.projection_params[0]);
    if (type == "eucm") k.required("beta", cam.projection_params[1]);
  } else {
    c.fail("camera_type", "expected pinhole, kb4, ds, eucm or unified, found '" + type + "'");
  }
  k.finish();
  return cam;
}

double largest(YamlOptionsReader& r, const std::string& key) {
  std::vector<double> v;
  r.required(key, v);
  r.check(v.size() == 3, key, "expected 3 numbers (x, y, z)");
  const double m = *std::max_element(v.begin(), v.end());
  r.check(m > 0, key, "must be positive");
  return m;
}

// calib_accel_bias: [b (3), s1..s6] with a_c = (I + [s1 0 0; s2 s4 0; s3 s5 s6]) a_raw - b;
// calib_gyro_bias: [b (3), s1..s9] with w_c = (I + S) w_raw - b, S filled column by column.
// The scale matrices become Ta, Tw (a_raw = Ta a_c); the static biases are left to the estimator.
void readImuScale(YamlOptionsReader& r, const std::string& key, size_t count, Eigen::Matrix3d& T, RigCalibration& rig) {
  std::vector<double> v;
  if (!r.optional(key, v)) return;
  r.check(v.size() == count, key, "expected " + std::to_string(count) + " numbers, found " + std::to_string(v.size()));
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  if (count == 9) {
    S << v[3], 0, 0, v[4], v[6], 0, v[5], v[7], v[8];
  } else {
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) S(row, c) = v[static_cast<size_t>(3 + 3 * c + row)];
  }
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() + S;
  r.check(std::abs(A.determinant()) > 1e-6, key, "the scale matrix is singular");
  T = A.inverse();
  if (S.isZero(0)) T = Eigen::Matrix3d::Identity();  // exactly, so that isIdentity() holds
  if (v[0] != 0 || v[1] != 0 || v[2] != 0)
    rig.ignored_keys.push_back(r.source() + ": " + key + "[0..2] (static biases: the estimator estimates its own)");
}

}  // namespace

bool isBasaltFile(const YamlOptionsReader& root) {
  if (!root.has("value0")) return false;
  YAML::Node v = root.peek("value0");
  return v.IsMap() && v["T_imu_cam"].IsDefined();
}

void readBasaltFile(YamlOptionsReader root, RigCalibration& rig) {
  YamlOptionsReader r = root.child("value0", true);
  std::vector<YamlOptionsReader> poses = mapList(r, "T_imu_cam");
  std::vector<YamlOptionsReader> intrinsics = mapList(r, "intrinsics");
  std::vector<std::vector<double>> resolution;
  r.required("resolution", resolution);
  r.check(!intrinsics.empty(), "intrinsics", "no camera");
  r.check(poses.size() == intrinsics.size() && resolution.size() == intrinsics.size(), "T_imu_cam",
          std::to_string(poses.size()) + " poses, " + std::to_string(intrinsics.size()) + " intrinsics and " +
              std::to_string(resolution.size()) + " resolutions: one of each per camera");
  int64_t offset_ns = 0;
  r.optional("cam_time_offset_ns", offset_ns);
  for (size_t i = 0; i < intrinsics.size(); ++i) {
    RigCamera cam;
    cam.source = r.source();
    cam.camera = readIntrinsics(intrinsics[i]);
    collectIgnored(intrinsics[i], rig);
    const auto& wh = resolution[i];
    // Range first: casting a huge double to int is undefined.
    r.check(wh.size() == 2 && wh[0] >= 1 && wh[1] >= 1 && wh[0] <= 1e5 && wh[1] <= 1e5 &&
                wh[0] == static_cast<int>(wh[0]) && wh[1] == static_cast<int>(wh[1]),
            "resolution", "expected [width, height] for camera " + std::to_string(i));
    cam.camera.width = static_cast<int>(wh[0]);
    cam.camera.height = static_cast<int>(wh[1]);
    try {
      CameraModel check(cam.camera);
    } catch (const std::invalid_argument& e) {
      intrinsics[i].fail("intrinsics", e.what());
    }
    cam.camera.T_B_C = readPose(poses[i]);
    cam.has_T_imu_cam = true;
    cam.time_offset_s = static_cast<double>(offset_ns) * 1e-9;
    rig.cameras.push_back(cam);
  }
  if (r.has("accel_noise_std")) {
    rig.has_imu = true;
    rig.imu = RigImu{};
    rig.imu.source = r.source();
    ImuNoise& n = rig.imu.noise;
    n.accel_noise_density = largest(r, "accel_noise_std");
    n.gyro_noise_density = largest(r, "gyro_noise_std");
    n.accel_random_walk = largest(r, "accel_bias_std");
    n.gyro_random_walk = largest(r, "gyro_bias_std");
    r.optional("imu_update_rate", n.rate_hz, 1.0, 1e5);
  }
  readImuScale(r, "calib_accel_bias", 9, rig.imu.intrinsics.Ta, rig);
  readImuScale(r, "calib_gyro_bias", 12, rig.imu.intrinsics.Tw, rig);
  collectIgnored(r, rig);
  collectIgnored(root, rig);
}

}  // namespace adugs::data

#include "data/formats/kalibr_calibration.h"

#include <vector>

#include "data/camera_model.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/yaml_options.h"

namespace adugs::data {
namespace {

Eigen::Matrix4d readMatrix4(YamlOptionsReader& r, const std::string& key) {
  std::vector<std::vector<double>> rows;
  r.required(key, rows);
  bool square = rows.size() == 4;
  for (const auto& row : rows) square = square && row.size() == 4;
  r.check(square, key, "expected a 4x4 matrix as 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = rows[i][j];
  return m;
}

Eigen::Isometry3d readKalibrTransform(YamlOptionsReader& r, const std::string& key) {
  return rigidTransform(r, key, readMatrix4(r, key), kForeignRigidTolerance);
}

// A 3x3 block as rows; absent keys keep `value`.
void readMatrix3(YamlOptionsReader& r, const std::string& key, Eigen::Matrix3d& value) {
  std::vector<std::vector<double>> rows;
  if (!r.optional(key, rows)) return;
  bool square = rows.size() == 3;
  for (const auto& row : rows) square = square && row.size() == 3;
  r.check(square, key, "expected a 3x3 matrix as 3 rows of 3 numbers");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) value(i, j) = rows[i][j];
}

void readRotation(YamlOptionsReader& r, const std::string& key, Eigen::Matrix3d& value) {
  readMatrix3(r, key, value);
  const double ortho = (value.transpose() * value - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  r.check(ortho <= kForeignRigidTolerance && std::abs(value.determinant() - 1) <= kForeignRigidTolerance, key,
          "not a rotation matrix");
}

void readInvertible(YamlOptionsReader& r, const std::string& key, Eigen::Matrix3d& value) {
  readMatrix3(r, key, value);
  r.check(std::abs(value.determinant()) > 1e-6, key, "a singular matrix cannot be inverted");
}

// camera_model and intrinsics in Kalibr's order: pinhole [fu fv pu pv], omni [xi fu fv pu pv],
// ds [xi alpha fu fv pu pv], eucm [alpha beta fu fv pu pv].
void readProjection(YamlOptionsReader& r, CameraCalibration& cam) {
  std::string model;
  r.required("camera_model", model);
  if (model == "pinhole") cam.projection = ProjectionModel::kPinhole;
  else if (model == "omni") cam.projection = ProjectionModel::kUnified;
  else if (model == "ds") cam.projection = ProjectionModel::kDoubleSphere;
  else if (model == "eucm") cam.projection = ProjectionModel::kExtendedUnified;
  else r.fail("camera_model", "expected pinhole, omni, ds or eucm, found '" + model + "'");
  const size_t extra = static_cast<size_t>(projectionParameterCount(cam.projection));
  std::vector<double> k;
  r.required("intrinsics", k);
  r.check(k.size() == extra + 4, "intrinsics",
          "camera_model " + model + " has " + std::to_string(extra + 4) + " intrinsics, found " +
              std::to_string(k.size()));
  cam.projection_params.assign(k.begin(), k.begin() + static_cast<long>(extra));
  cam.fx = k[extra];
  cam.fy = k[extra + 1];
  cam.cx = k[extra + 2];
  cam.cy = k[extra + 3];
  r.check(cam.fx > 0 && cam.fy > 0, "intrinsics", "focal lengths fu, fv must be positive");
}

void readDistortion(YamlOptionsReader& r, CameraCalibration& cam) {
  std::string dist = "none";
  const bool needed = cam.projection == ProjectionModel::kPinhole || cam.projection == ProjectionModel::kUnified;
  if (needed) r.required("distortion_model", dist);
  else r.optional("distortion_model", dist);
  if (dist == "none") {
    cam.distortion_model = DistortionModel::kNone;
    std::vector<double> coeffs;
    r.optional("distortion_coeffs", coeffs);
    for (double c : coeffs) r.check(c == 0, "distortion_coeffs", "distortion_model none has no coefficients");
    cam.distortion.assign(4, 0.0);
    return;
  }
  r.check(parseDistortionModel(dist, cam.distortion_model), "distortion_model",
          "expected radtan, equidistant or none, found '" + dist + "'");
  r.check(cam.projection == ProjectionModel::kPinhole ||
              (cam.projection == ProjectionModel::kUnified && cam.distortion_model == DistortionModel::kRadialTangential),
          "distortion_model", "camera_model " + toString(cam.projection) + " takes no '" + dist + "' distortion");
  r.required("distortion_coeffs", cam.distortion);
  r.check(cam.distortion.size() == 4, "distortion_coeffs",
          "expected 4 coefficients, found " + std::to_string(cam.distortion.size()));
}

void collectIgnored(const YamlOptionsReader& r, RigCalibration& rig) {
  for (const std::string& key : r.unusedKeys()) rig.ignored_keys.push_back(r.source() + ": " + key);
}

}  // namespace

RigCamera readKalibrCameraMap(YamlOptionsReader& r) {
  RigCamera out;
  out.source = r.source();
  CameraCalibration& cam = out.camera;
  readProjection(r, cam);
  readDistortion(r, cam);
  std::vector<int> resolution;
  r.required("resolution", resolution);
  r.check(resolution.size() == 2 && resolution[0] > 0 && resolution[1] > 0, "resolution",
          "expected [width, height], both positive");
  cam.width = resolution[0];
  cam.height = resolution[1];
  try {
    CameraModel check(cam);  // parameter ranges (DS alpha, EUCM beta, ...)
  } catch (const std::invalid_argument& e) {
    r.fail("intrinsics", e.what());
  }

  r.check(!(r.has("T_cam_imu") && r.has("T_imu_cam")), "T_imu_cam",
          "both T_cam_imu and T_imu_cam are given: keep one");
  if (r.has("T_cam_imu")) {
    cam.T_B_C = readKalibrTransform(r, "T_cam_imu").inverse();
    out.has_T_imu_cam = true;
  } else if (r.has("T_imu_cam")) {  // OpenVINS: camera -> IMU
    cam.T_B_C = readKalibrTransform(r, "T_imu_cam");
    out.has_T_imu_cam = true;
  }
  r.optional("timeshift_cam_imu", out.time_offset_s, -1.0, 1.0);
  r.optional("rostopic", out.rostopic);
  r.optional("rate_hz", cam.rate_hz, 0.0, 1e4);
  return out;
}

RigImu readKalibrImuMap(YamlOptionsReader& r, std::vector<std::string>* nested_unused) {
  RigImu out;
  out.source = r.source();
  ImuNoise& n = out.noise;
  r.required("accelerometer_noise_density", n.accel_noise_density, 1e-12, 1e3);
  r.required("accelerometer_random_walk", n.accel_random_walk, 1e-12, 1e3);
  r.required("gyroscope_noise_density", n.gyro_noise_density, 1e-12, 1e3);
  r.required("gyroscope_random_walk", n.gyro_random_walk, 1e-12, 1e3);
  r.optional("update_rate", n.rate_hz, 1.0, 1e5);
  r.optional("rostopic", out.rostopic);
  if (r.has("T_i_b")) n.T_B_I = readKalibrTransform(r, "T_i_b").inverse();

  // Intrinsics: OpenVINS' flat keys, or Kalibr's result blocks (the same matrices).
  std::string model = "calibrated";
  r.optional("model", model);
  ImuIntrinsics& in = out.intrinsics;
  readInvertible(r, "Tw", in.Tw);
  readRotation(r, "R_IMUtoGYRO", in.R_imu_gyro);
  readMatrix3(r, "Tg", in.Tg);
  readInvertible(r, "Ta", in.Ta);
  readRotation(r, "R_IMUtoACC", in.R_imu_acc);
  YamlOptionsReader gyro = r.child("gyroscopes");
  readInvertible(gyro, "M", in.Tw);
  readMatrix3(gyro, "A", in.Tg);
  readRotation(gyro, "C_gyro_i", in.R_imu_gyro);
  YamlOptionsReader acc = r.child("accelerometers");
  readInvertible(acc, "M", in.Ta);
  const bool size_effect = gyro.has("rx_i") || acc.has("rx_i") || r.has("rx_i") ||
                           model == "scale-misalignment-size-effect";
  r.check(!size_effect, "model",
          "Kalibr's scale-misalignment-size-effect model (accelerometer lever arms rx_i, ry_i, rz_i) "
          "is not modelled here; calibrate with the scale-misalignment model");
  r.check(model == "calibrated" || model == "kalibr" || model == "rpng" || model == "scale-misalignment",
          "model", "expected calibrated, kalibr, rpng or scale-misalignment, found '" + model + "'");
  // time_offset is imu0's offset to itself in a one-IMU rig (Kalibr writes 0).
  double time_offset = 0;
  r.optional("time_offset", time_offset, -1.0, 1.0);
  r.check(time_offset == 0, "time_offset",
          "a non-zero offset of the IMU to the reference IMU needs a second IMU; give "
          "timeshift_cam_imu in the camera file for the camera-IMU offset");
  for (const YamlOptionsReader* block : {&gyro, &acc}) {
    if (!nested_unused) block->finish();
    else for (const std::string& key : block->unusedKeys()) nested_unused->push_back(block->source() + ": " + key);
  }
  return out;
}

void readKalibrCamchain(YamlOptionsReader root, RigCalibration& rig) {
  const size_t first = rig.cameras.size();
  for (int i = 0; root.has("cam" + std::to_string(i)); ++i) {
    YamlOptionsReader r = root.child("cam" + std::to_string(i));
    RigCamera cam = readKalibrCameraMap(r);
    // A camchain without the IMU chains its cameras: T_cn_cnm1 maps cam(n-1) points into cam n.
    if (r.has("T_cn_cnm1")) {
      const Eigen::Isometry3d T_cn_cnm1 = readKalibrTransform(r, "T_cn_cnm1");
      if (!cam.has_T_imu_cam && rig.cameras.size() > first && rig.cameras.back().has_T_imu_cam) {
        cam.camera.T_B_C = rig.cameras.back().camera.T_B_C * T_cn_cnm1.inverse();
        cam.has_T_imu_cam = true;
      }
    }
    std::vector<int> overlaps;
    r.optional("cam_overlaps", overlaps);
    collectIgnored(r, rig);
    rig.cameras.push_back(std::move(cam));
  }
  if (rig.cameras.size() == first) root.fail("cam0", "missing required key (a camchain names its cameras cam0, cam1, ...)");
  collectIgnored(root, rig);
}

void readKalibrImu(YamlOptionsReader root, RigCalibration& rig) {
  rig.has_imu = true;
  if (root.has("imu0")) {
    YamlOptionsReader r = root.child("imu0");
    rig.imu = readKalibrImuMap(r, &rig.ignored_keys);
    collectIgnored(r, rig);
    collectIgnored(root, rig);
    return;
  }
  rig.imu = readKalibrImuMap(root, &rig.ignored_keys);  // Kalibr's documented input form: the keys at the top
  collectIgnored(root, rig);
}

RigCamera parseKalibrCamchain(const std::string& text, const std::string& source) {
  RigCalibration rig;
  readKalibrCamchain(YamlOptionsReader::fromString(text, source), rig);
  return rig.cameras.front();
}

RigImu parseKalibrImu(const std::string& text, const std::string& source) {
  RigCalibration rig;
  readKalibrImu(YamlOptionsReader::fromString(text, source), rig);
  return rig.imu;
}

}  // namespace adugs::data

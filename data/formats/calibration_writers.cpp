#include "data/formats/calibration_writers.h"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "data/formats/number_text.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {

std::string num(double v) { return shortestText(v); }
std::string list(const std::vector<double>& v) { return listText(v); }

std::string yamlRows(const Eigen::MatrixXd& m, const std::string& indent) {
  std::string s;
  for (int r = 0; r < m.rows(); ++r) {
    s += indent + "- [";
    for (int c = 0; c < m.cols(); ++c) s += (c ? ", " : "") + num(m(r, c));
    s += "]\n";
  }
  return s;
}

std::string jsonString(const std::string& text) {
  std::string s = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') s += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      s += ' ';
      continue;
    }
    s += c;
  }
  return s + "\"";
}

std::string jsonNumber(double v) { return std::isfinite(v) ? num(v) : "null"; }

[[noreturn]] void refuse(const std::string& tool, const std::string& field, const std::string& what) {
  throw InputError("--to " + tool, 0, field, what);
}

void requireImu(const RigCalibration& rig, const std::string& tool) {
  if (!rig.has_imu) refuse(tool, "imu", "the calibration has no IMU: give its IMU file as well");
  if (rig.imu.noise_per_sample)
    refuse(tool, "imu", "VINS' per-sample noise needs the IMU rate to become densities: give --imu-rate");
}

void requireExtrinsics(const RigCalibration& rig, const std::string& tool) {
  if (rig.cameras.empty()) refuse(tool, "cameras", "the calibration has no camera");
  for (size_t i = 0; i < rig.cameras.size(); ++i)
    if (!rig.cameras[i].has_T_imu_cam)
      refuse(tool, "cam" + std::to_string(i) + ".T_cam_imu", "the camera-IMU transform is missing");
}

// Kalibr's camera_model and intrinsics list ([xi] [alpha beta] fu fv pu pv).
std::string kalibrCamera(const CameraCalibration& c, const std::string& indent) {
  std::vector<double> k = c.projection_params;
  k.insert(k.end(), {c.fx, c.fy, c.cx, c.cy});
  const std::string dist = c.distortion_model == DistortionModel::kNone ? "none"
                           : c.distortion_model == DistortionModel::kEquidistant ? "equidistant"
                                                                                 : "radtan";
  std::string s = indent + "camera_model: " + toString(c.projection) + "\n";
  s += indent + "intrinsics: " + list(k) + "\n";
  s += indent + "distortion_model: " + dist + "\n";
  s += indent + "distortion_coeffs: " + list(c.distortion_model == DistortionModel::kNone ? std::vector<double>{} : c.distortion) + "\n";
  s += indent + "resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n";
  return s;
}

std::string camchain(const RigCalibration& rig, bool openvins) {
  std::string s = openvins ? "%YAML:1.0\n\n" : "";
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const RigCamera& cam = rig.cameras[i];
    s += "cam" + std::to_string(i) + ":\n";
    if (openvins) {
      s += "  T_imu_cam: # camera -> IMU (R_CtoI, p_CinI)\n" + yamlRows(cam.camera.T_B_C.matrix(), "    ");
    } else {
      s += "  T_cam_imu: # IMU -> camera\n" + yamlRows(cam.camera.T_B_C.inverse().matrix(), "    ");
      if (i > 0)
        s += "  T_cn_cnm1:\n" +
             yamlRows((cam.camera.T_B_C.inverse() * rig.cameras[i - 1].camera.T_B_C).matrix(), "    ");
    }
    s += "  cam_overlaps: []\n";
    s += kalibrCamera(cam.camera, "  ");
    s += "  rostopic: " + (cam.rostopic.empty() ? "/cam" + std::to_string(i) + "/image_raw" : cam.rostopic) + "\n";
    s += "  timeshift_cam_imu: " + num(cam.time_offset_s) + "\n";
  }
  return s;
}

std::string imuChain(const RigCalibration& rig, bool openvins) {
  const RigImu& imu = rig.imu;
  const ImuNoise& n = imu.noise;
  std::string s = openvins ? "%YAML:1.0\n\n" : "";
  s += "imu0:\n";
  s += "  T_i_b:\n" + yamlRows(n.T_B_I.inverse().matrix(), "    ");
  s += "  accelerometer_noise_density: " + num(n.accel_noise_density) + "\n";
  s += "  accelerometer_random_walk: " + num(n.accel_random_walk) + "\n";
  s += "  gyroscope_noise_density: " + num(n.gyro_noise_density) + "\n";
  s += "  gyroscope_random_walk: " + num(n.gyro_random_walk) + "\n";
  s += "  rostopic: " + (imu.rostopic.empty() ? std::string("/imu0") : imu.rostopic) + "\n";
  s += "  time_offset: 0.0\n";
  if (n.rate_hz > 0) s += "  update_rate: " + num(n.rate_hz) + "\n";
  const ImuIntrinsics& in = imu.intrinsics;
  if (openvins) {
    s += "  model: kalibr\n";
    s += "  Tw:\n" + yamlRows(in.Tw, "    ") + "  R_IMUtoGYRO:\n" + yamlRows(in.R_imu_gyro, "    ");
    s += "  Ta:\n" + yamlRows(in.Ta, "    ") + "  R_IMUtoACC:\n" + yamlRows(in.R_imu_acc, "    ");
    s += "  Tg:\n" + yamlRows(in.Tg, "    ");
  } else if (!in.isIdentity()) {
    if (!in.R_imu_acc.isIdentity(0)) refuse("kalibr", "R_IMUtoACC", "Kalibr's IMU model has no accelerometer rotation");
    s += "  model: scale-misalignment\n";
    s += "  gyroscopes:\n    M:\n" + yamlRows(in.Tw, "      ") + "    A:\n" + yamlRows(in.Tg, "      ");
    s += "    C_gyro_i:\n" + yamlRows(in.R_imu_gyro, "      ");
    s += "  accelerometers:\n    M:\n" + yamlRows(in.Ta, "      ");
  } else {
    s += "  model: calibrated\n";
  }
  return s;
}

std::string openCvMatrix(const std::string& key, const Eigen::Matrix4d& m) {
  std::string s = key + ": !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n   data: [";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s += (r || c ? ", " : "") + num(m(r, c));
  return s + "]\n";
}

std::string vinsCamera(const CameraCalibration& c, size_t i) {
  const std::string field = "cam" + std::to_string(i);
  std::string s = "%YAML:1.0\n---\n";
  const bool radtan = c.distortion_model == DistortionModel::kRadialTangential || c.distortion_model == DistortionModel::kNone;
  auto distortion = [&] {
    return "distortion_parameters:\n   k1: " + num(c.distortion[0]) + "\n   k2: " + num(c.distortion[1]) +
           "\n   p1: " + num(c.distortion[2]) + "\n   p2: " + num(c.distortion[3]) + "\n";
  };
  const std::string size = "camera_name: camera\nimage_width: " + std::to_string(c.width) +
                           "\nimage_height: " + std::to_string(c.height) + "\n";
  if (c.projection == ProjectionModel::kPinhole && radtan) {
    s += "model_type: PINHOLE\n" + size + distortion();
    s += "projection_parameters:\n   fx: " + num(c.fx) + "\n   fy: " + num(c.fy) + "\n   cx: " + num(c.cx) +
         "\n   cy: " + num(c.cy) + "\n";
  } else if (c.projection == ProjectionModel::kPinhole) {
    s += "model_type: KANNALA_BRANDT\n" + size;
    s += "projection_parameters:\n   k2: " + num(c.distortion[0]) + "\n   k3: " + num(c.distortion[1]) +
         "\n   k4: " + num(c.distortion[2]) + "\n   k5: " + num(c.distortion[3]) + "\n   mu: " + num(c.fx) +
         "\n   mv: " + num(c.fy) + "\n   u0: " + num(c.cx) + "\n   v0: " + num(c.cy) + "\n";
  } else if (c.projection == ProjectionModel::kUnified && radtan) {
    s += "model_type: MEI\n" + size + "mirror_parameters:\n   xi: " + num(c.projection_params[0]) + "\n" + distortion();
    s += "projection_parameters:\n   gamma1: " + num(c.fx) + "\n   gamma2: " + num(c.fy) + "\n   u0: " + num(c.cx) +
         "\n   v0: " + num(c.cy) + "\n";
  } else {
    refuse("vins", field + ".camera_model", "VINS has no " + toString(c.projection) + " camera (PINHOLE, MEI, KANNALA_BRANDT)");
  }
  return s;
}

CalibrationFiles vins(const RigCalibration& rig) {
  requireExtrinsics(rig, "vins");
  requireImu(rig, "vins");
  if (!(rig.imu.noise.rate_hz > 0))
    refuse("vins", "imu.update_rate", "VINS' noise figures are per IMU sample: the IMU rate is needed (give --imu-rate)");
  if (rig.cameras.size() > 2) refuse("vins", "cameras", "VINS-Fusion takes one or two cameras");
  if (!rig.imu.intrinsics.isIdentity()) refuse("vins", "imu.intrinsics", "VINS has no IMU intrinsics (Tw, Ta, Tg)");
  CalibrationFiles files;
  const ImuNoise& n = rig.imu.noise;
  const double sqrt_rate = std::sqrt(n.rate_hz);  // per-sample std = density / sqrt(dt)
  const RigCamera& cam0 = rig.cameras.front();
  std::string s = "%YAML:1.0\n\n# written by adugs calib convert --to vins\nimu: 1\nnum_of_cam: " +
                  std::to_string(rig.cameras.size()) + "\n";
  s += "imu_topic: \"" + (rig.imu.rostopic.empty() ? std::string("/imu0") : rig.imu.rostopic) + "\"\n";
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const std::string name = "cam" + std::to_string(i) + ".yaml";
    files.emplace_back(name, vinsCamera(rig.cameras[i].camera, i));
    s += "image" + std::to_string(i) + "_topic: \"" +
         (rig.cameras[i].rostopic.empty() ? "/cam" + std::to_string(i) + "/image_raw" : rig.cameras[i].rostopic) + "\"\n";
    s += "cam" + std::to_string(i) + "_calib: \"" + name + "\"\n";
  }
  s += "image_width: " + std::to_string(cam0.camera.width) + "\nimage_height: " + std::to_string(cam0.camera.height) + "\n";
  s += "estimate_extrinsic: 1\n";
  for (size_t i = 0; i < rig.cameras.size(); ++i)
    s += openCvMatrix("body_T_cam" + std::to_string(i), rig.cameras[i].camera.T_B_C.matrix());
  s += "# per-sample standard deviations (density * sqrt(" + num(n.rate_hz) + " Hz))\n";
  s += "acc_n: " + num(n.accel_noise_density * sqrt_rate) + "\n";
  s += "gyr_n: " + num(n.gyro_noise_density * sqrt_rate) + "\n";
  s += "acc_w: " + num(n.accel_random_walk * sqrt_rate) + "\n";
  s += "gyr_w: " + num(n.gyro_random_walk * sqrt_rate) + "\n";
  s += "g_norm: 9.81\nestimate_td: 0\ntd: " + num(cam0.time_offset_s) + "\n";
  files.insert(files.begin(), {"config.yaml", s});
  return files;
}

std::string basaltPose(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d p = T.translation();
  return "{\"px\": " + num(p.x()) + ", \"py\": " + num(p.y()) + ", \"pz\": " + num(p.z()) + ", \"qx\": " + num(q.x()) +
         ", \"qy\": " + num(q.y()) + ", \"qz\": " + num(q.z()) + ", \"qw\": " + num(q.w()) + "}";
}

std::string basaltIntrinsics(const CameraCalibration& c, size_t i) {
  const std::string head = "\"fx\": " + num(c.fx) + ", \"fy\": " + num(c.fy) + ", \"cx\": " + num(c.cx) + ", \"cy\": " + num(c.cy);
  const bool no_distortion = c.distortion_model == DistortionModel::kNone ||
                             (c.distortion_model == DistortionModel::kRadialTangential &&
                              c.distortion == std::vector<double>{0, 0, 0, 0});
  std::string type, rest;
  if (c.projection == ProjectionModel::kPinhole && c.distortion_model == DistortionModel::kEquidistant) {
    type = "kb4";
    rest = ", \"k1\": " + num(c.distortion[0]) + ", \"k2\": " + num(c.distortion[1]) + ", \"k3\": " + num(c.distortion[2]) +
           ", \"k4\": " + num(c.distortion[3]);
  } else if (c.projection == ProjectionModel::kPinhole && no_distortion) {
    type = "pinhole";
  } else if (c.projection == ProjectionModel::kDoubleSphere) {
    type = "ds";
    rest = ", \"xi\": " + num(c.projection_params[0]) + ", \"alpha\": " + num(c.projection_params[1]);
  } else if (c.projection == ProjectionModel::kExtendedUnified) {
    type = "eucm";
    rest = ", \"alpha\": " + num(c.projection_params[0]) + ", \"beta\": " + num(c.projection_params[1]);
  } else {
    refuse("basalt", "cam" + std::to_string(i) + ".camera_model",
           "Basalt has no " + toString(c.projection) + " camera with " + toString(c.distortion_model) +
               " distortion (pinhole without distortion, kb4, ds, eucm): --model ds, eucm or equidistant refits the lens");
  }
  return "{\"camera_type\": \"" + type + "\", \"intrinsics\": {" + head + rest + "}}";
}

std::string basalt(const RigCalibration& rig) {
  requireExtrinsics(rig, "basalt");
  requireImu(rig, "basalt");
  const ImuIntrinsics& in = rig.imu.intrinsics;
  const Eigen::Matrix3d Sa = in.Ta.inverse() - Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Sg = in.Tw.inverse() - Eigen::Matrix3d::Identity();
  if (!in.R_imu_gyro.isIdentity(0) || !in.R_imu_acc.isIdentity(0) || !in.Tg.isZero(0) ||
      std::abs(Sa(0, 1)) + std::abs(Sa(0, 2)) + std::abs(Sa(1, 2)) > 1e-12)
    refuse("basalt", "imu.intrinsics",
           "Basalt's IMU model has a lower-triangular accelerometer scale and a full gyroscope scale, no rotations or "
           "g-sensitivity");
  const bool identity = in.isIdentity();
  auto scales = [](const std::vector<double>& v) {
    std::string t = "[0, 0, 0";
    for (double x : v) t += ", " + num(x);
    return t + "]";
  };
  const ImuNoise& n = rig.imu.noise;
  auto three = [](double v) { return "[" + num(v) + ", " + num(v) + ", " + num(v) + "]"; };
  std::string poses, intr, res;
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const CameraCalibration& c = rig.cameras[i].camera;
    poses += std::string(i ? ",\n" : "") + "      " + basaltPose(c.T_B_C);
    intr += std::string(i ? ",\n" : "") + "      " + basaltIntrinsics(c, i);
    res += std::string(i ? ", " : "") + "[" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]";
  }
  std::string s = "{\n  \"value0\": {\n";
  s += "    \"T_imu_cam\": [\n" + poses + "\n    ],\n";
  s += "    \"intrinsics\": [\n" + intr + "\n    ],\n";
  s += "    \"resolution\": [" + res + "],\n";
  s += "    \"calib_accel_bias\": " +
       (identity ? std::string("[0, 0, 0, 0, 0, 0, 0, 0, 0]")
                 : scales({Sa(0, 0), Sa(1, 0), Sa(2, 0), Sa(1, 1), Sa(2, 1), Sa(2, 2)})) + ",\n";
  s += "    \"calib_gyro_bias\": " +
       (identity ? std::string("[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]")
                 : scales({Sg(0, 0), Sg(1, 0), Sg(2, 0), Sg(0, 1), Sg(1, 1), Sg(2, 1), Sg(0, 2), Sg(1, 2), Sg(2, 2)})) + ",\n";
  s += "    \"imu_update_rate\": " + num(n.rate_hz > 0 ? n.rate_hz : 200.0) + ",\n";
  s += "    \"accel_noise_std\": " + three(n.accel_noise_density) + ",\n";
  s += "    \"gyro_noise_std\": " + three(n.gyro_noise_density) + ",\n";
  s += "    \"accel_bias_std\": " + three(n.accel_random_walk) + ",\n";
  s += "    \"gyro_bias_std\": " + three(n.gyro_random_walk) + ",\n";
  s += "    \"cam_time_offset_ns\": " + std::to_string(std::llround(rig.cameras.front().time_offset_s * 1e9)) + "\n";
  return s + "  }\n}\n";
}

}  // namespace

std::vector<std::string> calibrationWriterNames() { return {"kalibr", "openvins", "vins", "basalt"}; }

CalibrationFiles formatCalibration(const RigCalibration& rig, const std::string& tool) {
  if (tool == "kalibr" || tool == "openvins") {
    const bool ov = tool == "openvins";
    requireExtrinsics(rig, tool);
    requireImu(rig, tool);
    if (ov)
      for (size_t i = 0; i < rig.cameras.size(); ++i)
        if (rig.cameras[i].camera.projection != ProjectionModel::kPinhole ||
            rig.cameras[i].camera.distortion_model == DistortionModel::kNone)
          refuse(tool, "cam" + std::to_string(i) + ".camera_model",
                 "OpenVINS has pinhole cameras with radtan or equidistant distortion only");
    return {{ov ? "kalibr_imucam_chain.yaml" : "camchain-imucam.yaml", camchain(rig, ov)},
            {ov ? "kalibr_imu_chain.yaml" : "imu.yaml", imuChain(rig, ov)}};
  }
  if (tool == "vins") return vins(rig);
  if (tool == "basalt") return {{"calib.json", basalt(rig)}};
  throw InputError("--to", 0, "to", "unknown tool '" + tool + "' (kalibr, openvins, vins, basalt)");
}

std::string formatCalibrationJson(const RigCalibration& rig) {
  std::string s = "{\n  \"cameras\": [";
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const RigCamera& cam = rig.cameras[i];
    const CameraCalibration& c = cam.camera;
    std::string model = c.projection == ProjectionModel::kUnified       ? "mei"
                        : c.projection == ProjectionModel::kDoubleSphere ? "ds"
                        : c.projection == ProjectionModel::kExtendedUnified ? "eucm"
                        : c.distortion_model == DistortionModel::kEquidistant ? "equidistant"
                                                                               : "pinhole";
    const std::string dist = c.distortion_model == DistortionModel::kNone ? "none"
                             : c.distortion_model == DistortionModel::kEquidistant ? "equidistant"
                                                                                   : "radtan";
    std::vector<double> k = {c.fx, c.fy, c.cx, c.cy};
    k.insert(k.end(), c.projection_params.begin(), c.projection_params.end());
    s += std::string(i ? "," : "") + "\n    {\"model\": \"" + model + "\", \"intrinsics\": " + list(k) +
         ", \"distortion_model\": \"" + dist + "\", \"distortion\": " +
         list(c.distortion_model == DistortionModel::kNone ? std::vector<double>{} : c.distortion) +
         ", \"resolution\": [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "], \"T_imu_cam\": ";
    if (cam.has_T_imu_cam) {
      const Eigen::Matrix4d T = c.T_B_C.matrix();
      s += "[";
      for (int r = 0; r < 4; ++r) {
        s += r ? ", [" : "[";
        for (int col = 0; col < 4; ++col) s += (col ? ", " : "") + num(T(r, col));
        s += "]";
      }
      s += "]";
    } else {
      s += "null";
    }
    s += ", \"time_offset_s\": " + jsonNumber(cam.time_offset_s) + ", \"rostopic\": " + jsonString(cam.rostopic) +
         ", \"source\": " + jsonString(cam.source) + "}";
  }
  s += rig.cameras.empty() ? "],\n" : "\n  ],\n";
  if (rig.has_imu) {
    const ImuNoise& n = rig.imu.noise;
    const bool ok = !rig.imu.noise_per_sample;
    auto val = [&](double v) { return ok ? jsonNumber(v) : std::string("null"); };
    s += "  \"imu\": {\"accelerometer_noise_density\": " + val(n.accel_noise_density) +
         ", \"accelerometer_random_walk\": " + val(n.accel_random_walk) +
         ", \"gyroscope_noise_density\": " + val(n.gyro_noise_density) +
         ", \"gyroscope_random_walk\": " + val(n.gyro_random_walk) +
         ", \"update_rate_hz\": " + (n.rate_hz > 0 ? jsonNumber(n.rate_hz) : "null");
    if (!ok)
      s += ", \"per_sample_std\": {\"acc_n\": " + jsonNumber(n.accel_noise_density) + ", \"gyr_n\": " +
           jsonNumber(n.gyro_noise_density) + ", \"acc_w\": " + jsonNumber(n.accel_random_walk) + ", \"gyr_w\": " +
           jsonNumber(n.gyro_random_walk) + "}";
    const ImuIntrinsics& in = rig.imu.intrinsics;
    if (!in.isIdentity()) {
      auto m3 = [](const Eigen::Matrix3d& m) {
        std::string t = "[";
        for (int r = 0; r < 3; ++r) t += std::string(r ? ", " : "") + "[" + num(m(r, 0)) + ", " + num(m(r, 1)) + ", " + num(m(r, 2)) + "]";
        return t + "]";
      };
      s += ", \"intrinsics\": {\"Tw\": " + m3(in.Tw) + ", \"R_IMUtoGYRO\": " + m3(in.R_imu_gyro) + ", \"Tg\": " + m3(in.Tg) +
           ", \"Ta\": " + m3(in.Ta) + ", \"R_IMUtoACC\": " + m3(in.R_imu_acc) + "}";
    }
    s += ", \"source\": " + jsonString(rig.imu.source) + "},\n";
  } else {
    s += "  \"imu\": null,\n";
  }
  s += "  \"files\": [";
  for (size_t i = 0; i < rig.files.size(); ++i)
    s += std::string(i ? ", " : "") + "{\"path\": " + jsonString(rig.files[i]) + ", \"format\": " + jsonString(rig.formats[i]) + "}";
  s += "],\n  \"ignored_keys\": [";
  for (size_t i = 0; i < rig.ignored_keys.size(); ++i) s += std::string(i ? ", " : "") + jsonString(rig.ignored_keys[i]);
  return s + "]\n}\n";
}

}  // namespace adugs::data

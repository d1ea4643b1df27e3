#include "data/formats/euroc_sensor_yaml.h"

#include <cmath>
#include <fstream>

#include "data/camera_model.h"
#include "data/formats/number_text.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace adugs::data {

Eigen::Isometry3d rigidTransform(const YamlOptionsReader& r, const std::string& key, const Eigen::Matrix4d& m,
                                 double tolerance) {
  Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  double ortho = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  double det = R.determinant();
  double last = (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  if (!(ortho <= tolerance && std::fabs(det - 1) <= tolerance && last <= tolerance)) {
    r.fail(key, "not a rigid transform (|R^T R - I| = " + detail::numberText(ortho) + ", det R = " +
                    detail::numberText(det) + ", last row off by " + detail::numberText(last) +
                    "; tolerance " + detail::numberText(tolerance) + ")");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

void readPinholeIntrinsics(YamlOptionsReader& r, CameraCalibration* cam) {
  std::string model;
  r.required("camera_model", model);
  // adugs writes a wide-angle lens as camera_model: omni | ds | eucm, so that another tool's
  // EuRoC reader refuses it instead of taking it for a pinhole (the projection parameters are
  // read with the rest of the sensor.yaml).
  r.check(parseProjectionModel(model, cam->projection), "camera_model",
          "expected 'pinhole', 'omni', 'ds' or 'eucm', found '" + model + "'");
  std::vector<double> k;
  r.required("intrinsics", k);
  r.check(k.size() == 4, "intrinsics", "expected [fu, fv, cu, cv], found " + std::to_string(k.size()) + " numbers");
  r.check(k[0] > 0 && k[1] > 0, "intrinsics", "focal lengths fu, fv must be positive");
  cam->fx = k[0];
  cam->fy = k[1];
  cam->cx = k[2];
  cam->cy = k[3];
}

namespace {

// The optional sensor_type and comment keys.
void readHeader(YamlOptionsReader& r, const std::string& expected_type) {
  std::string type, comment;
  if (r.optional("sensor_type", type)) {
    r.check(type == expected_type, "sensor_type", "expected '" + expected_type + "', found '" + type + "'");
  }
  r.optional("comment", comment);
}

Eigen::Isometry3d readEurocTransform(YamlOptionsReader& parent, const std::string& key) {
  YamlOptionsReader r = parent.child(key, true);
  int rows = 0, cols = 0;
  std::vector<double> data;
  r.required("rows", rows);
  r.required("cols", cols);
  r.required("data", data);
  r.finish();
  r.check(rows == 4, "rows", "expected 4, found " + std::to_string(rows));
  r.check(cols == 4, "cols", "expected 4, found " + std::to_string(cols));
  r.check(data.size() == 16, "data", "expected 16 numbers (4x4 row-major), found " + std::to_string(data.size()));

  return rigidTransform(r, "data", Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(data.data()));
}

void requirePositive(const YamlOptionsReader& r, const std::string& key, double v) {
  r.check(v > 0, key, "must be positive, found " + detail::numberText(v));
}


std::string transformYaml(const Eigen::Isometry3d& T) {
  std::string s = "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      s += shortestText(T.matrix()(r, c));
      s += c < 3 ? ", " : r < 3 ? ",\n         " : "]\n";
    }
  }
  return s;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw InputError(path, 0, "", "cannot write file");
}

}  // namespace

namespace {

CameraCalibration parseCamera(YamlOptionsReader r) {
  readHeader(r, "camera");
  CameraCalibration cam;
  cam.T_B_C = readEurocTransform(r, "T_BS");

  r.required("rate_hz", cam.rate_hz);
  requirePositive(r, "rate_hz", cam.rate_hz);

  std::vector<int> resolution;
  r.required("resolution", resolution);
  r.check(resolution.size() == 2, "resolution", "expected [width, height], found " +
                                                    std::to_string(resolution.size()) + " numbers");
  r.check(resolution[0] > 0 && resolution[1] > 0, "resolution", "width and height must be positive");
  cam.width = resolution[0];
  cam.height = resolution[1];

  readPinholeIntrinsics(r, &cam);

  // A wide-angle projection: named by camera_model (what adugs writes), or, as adugs wrote it
  // before, camera_model: pinhole with a `projection:` key. Absent: pinhole, as in every EuRoC file.
  std::string projection;
  if (r.optional("projection", projection)) {
    ProjectionModel named = ProjectionModel::kPinhole;
    r.check(parseProjectionModel(projection, named), "projection",
            "expected 'pinhole', 'omni', 'ds' or 'eucm', found '" + projection + "'");
    r.check(cam.projection == ProjectionModel::kPinhole || cam.projection == named, "projection",
            "'" + projection + "' disagrees with camera_model '" + toString(cam.projection) + "'");
    cam.projection = named;
  }
  const int n = projectionParameterCount(cam.projection);
  if (n > 0) r.required("projection_params", cam.projection_params);
  r.check(static_cast<int>(cam.projection_params.size()) == n, "projection_params",
          "camera model " + toString(cam.projection) + " takes " + std::to_string(n) + " parameters, found " +
              std::to_string(cam.projection_params.size()));

  std::string dist;
  r.required("distortion_model", dist);
  if (dist == "radial-tangential") {
    cam.distortion_model = DistortionModel::kRadialTangential;
  } else if (dist == "equidistant") {
    cam.distortion_model = DistortionModel::kEquidistant;
  } else if (dist == "none") {
    cam.distortion_model = DistortionModel::kNone;
  } else {
    r.fail("distortion_model",
           "expected 'radial-tangential', 'equidistant' or 'none', found '" + dist + "'");
  }
  r.required("distortion_coefficients", cam.distortion);
  r.check(cam.distortion.size() == 4, "distortion_coefficients",
          "expected 4 coefficients, found " + std::to_string(cam.distortion.size()));
  r.finish();
  return cam;
}

ImuNoise parseImu(YamlOptionsReader r) {
  readHeader(r, "imu");
  ImuNoise imu;
  if (r.has("T_BS")) imu.T_B_I = readEurocTransform(r, "T_BS");
  struct Field {
    const char* key;
    double* value;
  };
  for (Field f : {Field{"rate_hz", &imu.rate_hz}, Field{"gyroscope_noise_density", &imu.gyro_noise_density},
                  Field{"gyroscope_random_walk", &imu.gyro_random_walk},
                  Field{"accelerometer_noise_density", &imu.accel_noise_density},
                  Field{"accelerometer_random_walk", &imu.accel_random_walk}}) {
    r.required(f.key, *f.value);
    requirePositive(r, f.key, *f.value);
  }
  r.finish();
  return imu;
}

}  // namespace

CameraCalibration parseEurocCameraYaml(const std::string& text, const std::string& source) {
  return parseCamera(YamlOptionsReader::fromString(text, source));
}

CameraCalibration readEurocCameraYaml(const std::string& path) {
  return parseCamera(YamlOptionsReader::fromFile(path));
}

ImuNoise parseEurocImuYaml(const std::string& text, const std::string& source) {
  return parseImu(YamlOptionsReader::fromString(text, source));
}

ImuNoise readEurocImuYaml(const std::string& path) { return parseImu(YamlOptionsReader::fromFile(path)); }

std::string formatEurocCameraYaml(const CameraCalibration& c, const std::string& comment,
                                  const std::string& first_comment) {
  std::string quoted;  // a YAML double-quoted scalar
  for (char ch : comment) {
    if (ch == '"' || ch == '\\') quoted += '\\';
    quoted += ch == '\n' ? ' ' : ch;
  }
  std::string s = "%YAML:1.0\n" + first_comment + "# General sensor definitions.\nsensor_type: camera\n";
  s += "comment: \"" + quoted + "\"\n\n# Sensor extrinsics wrt. the body-frame.\n";
  s += transformYaml(c.T_B_C);
  s += "\n# Camera specific definitions.\n";
  s += "rate_hz: " + shortestText(c.rate_hz) + "\n";
  s += "resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n";
  // A wide-angle lens names its model here (a pinhole-only EuRoC reader then refuses the file
  // rather than misreading it); pinhole files stay plain EuRoC.
  s += "camera_model: " + toString(c.projection) + "\n";
  s += "intrinsics: " + listText({c.fx, c.fy, c.cx, c.cy}) + " #fu, fv, cu, cv\n";
  if (c.projection != ProjectionModel::kPinhole) s += "projection_params: " + listText(c.projection_params) + "\n";
  s += "distortion_model: " + toString(c.distortion_model) + "\n";
  s += "distortion_coefficients: " + listText(c.distortion) + "\n";
  return s;
}

std::string formatEurocImuYaml(const ImuNoise& imu) {
  std::string s = "%YAML:1.0\nsensor_type: imu\ncomment: written by adugs\n\n";
  s += "# Sensor extrinsics wrt. the body-frame.\n" + transformYaml(imu.T_B_I);
  s += "rate_hz: " + shortestText(imu.rate_hz) + "\n\n";
  s += "# inertial sensor noise model parameters (static)\n";
  s += "gyroscope_noise_density: " + shortestText(imu.gyro_noise_density) + "  # [ rad / s / sqrt(Hz) ]\n";
  s += "gyroscope_random_walk: " + shortestText(imu.gyro_random_walk) + "  # [ rad / s^2 / sqrt(Hz) ]\n";
  s += "accelerometer_noise_density: " + shortestText(imu.accel_noise_density) + "  # [ m / s^2 / sqrt(Hz) ]\n";
  s += "accelerometer_random_walk: " + shortestText(imu.accel_random_walk) + "  # [ m / s^3 / sqrt(Hz) ]\n";
  return s;
}

void writeEurocCameraYaml(const std::string& path, const CameraCalibration& camera, const std::string& comment,
                          const std::string& first_comment) {
  writeFile(path, formatEurocCameraYaml(camera, comment, first_comment));
}

void writeEurocImuYaml(const std::string& path, const ImuNoise& imu) {
  writeFile(path, formatEurocImuYaml(imu));
}

}  // namespace adugs::data

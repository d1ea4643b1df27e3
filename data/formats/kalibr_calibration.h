#pragma once
// Reading Kalibr calibration files, as dataset users and `adugs calib camera-imu` have them:
//   camchain-imucam.yaml   cam0: camera_model pinhole, intrinsics [fu fv pu pv],
//                          distortion_model radtan | equidistant, distortion_coeffs (4),
//                          resolution [w h], T_cam_imu (4x4, maps IMU-frame points into the
//                          camera frame), timeshift_cam_imu (s; t_imu = t_cam + shift), rostopic
//   imu.yaml               imu0: accelerometer/gyroscope noise densities and random walks,
//                          update_rate, rostopic, T_i_b, model, time_offset
// Converted at this boundary to the project's frames: T_B_C = T_cam_imu^-1 (body = IMU).
// Unknown keys, other camera models (omni, ds, eucm), other distortion models and non-rigid
// transforms are InputErrors naming the file, line and key.
#include <cstdint>
#include <string>

#include "data/formats/euroc_sensor_yaml.h"

namespace adugs::data {

struct KalibrCamera {
  CameraCalibration camera;  // T_B_C from T_cam_imu; identity when the file has no T_cam_imu
  bool has_T_cam_imu = false;
  int64_t time_shift_ns = 0;  // timeshift_cam_imu
  std::string rostopic;
};

struct KalibrImu {
  ImuNoise noise;
  std::string rostopic;
};

// `camera` is the camchain's top-level key ("cam0").
KalibrCamera readKalibrCamchain(const std::string& path, const std::string& camera = "cam0");
KalibrCamera parseKalibrCamchain(const std::string& text, const std::string& source,
                                 const std::string& camera = "cam0");
KalibrImu readKalibrImu(const std::string& path);
KalibrImu parseKalibrImu(const std::string& text, const std::string& source);

class YamlOptionsReader;
// One camera's map (the keys under "cam0:") and the IMU's map (the keys under "imu0:"), for files
// that embed them, such as data/config/d435i.yaml. Both call finish() on the reader.
KalibrCamera readKalibrCameraMap(YamlOptionsReader& camera);
KalibrImu readKalibrImuMap(YamlOptionsReader& imu);

}  // namespace adugs::data

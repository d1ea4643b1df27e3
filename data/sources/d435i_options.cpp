#include "data/sources/d435i_options.h"

#include "data/formats/yaml_options.h"

namespace adugs::data {

data::RigCamera D435iOptions::placeholderCamera() {
  // One D435i's factory intrinsics of the 640x480 infrared mode (385.75 px, VINS-Fusion's
  // config/realsense_d435i/left.yaml) scaled to the 848x480 mode (the 1280x800 imager scaled by
  // 0.6625 instead of 0.6): 426 px, principal point at the centre, no distortion. A placeholder:
  // every unit differs by a few pixels; calibrate (adugs calib intrinsics).
  data::RigCamera c;
  c.source = "the run config's d435i.cam0";
  c.camera.width = 848;
  c.camera.height = 480;
  c.camera.fx = c.camera.fy = 426.0;
  c.camera.cx = 424.0;
  c.camera.cy = 240.0;
  c.camera.distortion_model = data::DistortionModel::kRadialTangential;
  c.camera.distortion = {0, 0, 0, 0};
  // librealsense's CAD extrinsic of the D435i (ds-calib-parsers.cpp, used when the unit stores
  // none): depth (= left imager) to IMU, rotation I once the IMU axes are turned to the camera's,
  // translation t = (-5.52, 5.1, 11.74) mm, p_imu = p_depth + t; so T_B_C = [I | t].
  c.camera.T_B_C = Eigen::Isometry3d::Identity();
  c.camera.T_B_C.translation() = Eigen::Vector3d(-0.00552, 0.0051, 0.01174);
  c.has_T_imu_cam = true;
  c.camera.rate_hz = 30;
  return c;
}

data::ImuNoise D435iOptions::defaultImuNoise() {
  // What D435i users run with (rpng/open_vins config/rs435i/imu_rs435i.yaml), about 7x (accel) and
  // 20x (gyro) the BMI055 datasheet densities (150 ug/sqrt(Hz), 0.014 deg/s/sqrt(Hz)).
  data::ImuNoise n;
  n.accel_noise_density = 0.01;
  n.accel_random_walk = 0.0002;
  n.gyro_noise_density = 0.005;
  n.gyro_random_walk = 4.0e-6;
  n.rate_hz = 400;
  return n;
}

void readD435iOptions(data::YamlOptionsReader& r, D435iOptions* o) {
  r.optional("sys_root", o->sys_root);
  r.optional("dev_root", o->dev_root);
  r.optional("usb_id", o->usb_id);
  r.optional("serial", o->serial);
  r.optional("backend", o->backend);
  if (o->backend != "kernel" && o->backend != "librealsense") r.fail("backend", "must be kernel or librealsense");
  r.optional("stream", o->stream);
  if (o->stream != "infrared" && o->stream != "color") r.fail("stream", "must be infrared or color");
  r.optional("format", o->format);
  if (o->format != "auto" && o->format != "grey" && o->format != "y8i" && o->format != "yuyv")
    r.fail("format", "must be auto, grey, y8i or yuyv");
  if (o->stream == "color" && (o->format == "grey" || o->format == "y8i"))
    r.fail("format", "the colour camera sends yuyv");
  r.optional("width", o->width, 16, 8192);
  r.optional("height", o->height, 16, 8192);
  r.optional("fps", o->fps, 1.0, 1000.0);
  r.optional("buffers", o->buffers, 2, 64);
  r.optional("metadata", o->metadata);
  r.optional("emitter", o->emitter);
  if (o->emitter != "off" && o->emitter != "on" && o->emitter != "keep") r.fail("emitter", "must be off, on or keep");
  r.optional("exposure_us", o->exposure_us, 0, 1000000);
  r.optional("gain", o->gain, 0, 1000);
  if (o->gain > 0 && o->exposure_us == 0) r.fail("gain", "a manual gain needs a manual exposure (exposure_us > 0)");
  r.optional("imu", o->imu);
  r.optional("accel_hz", o->accel_hz, 1.0, 2000.0);
  r.optional("gyro_hz", o->gyro_hz, 1.0, 2000.0);
  r.optional("gyro_lsb_deg_s", o->gyro_lsb_deg_s, 0.0, 10.0);
  r.optional("iio_buffer_records", o->iio_buffer_records, 2, 1 << 20);
  r.optional("frame_latency_s", o->frame_latency_s, 0.001, 10.0);
  r.optional("imu_latency_s", o->imu_latency_s, 0.001, 10.0);
  r.optional("stall_timeout_s", o->stall_timeout_s, 0.1, 600.0);
  r.optional("clock_warmup_s", o->clock_warmup_s, 0.0, 60.0);
  if (r.has("cam0")) {
    data::YamlOptionsReader c = r.child("cam0");
    o->camera = data::readKalibrCameraMap(c);
    c.finish();
  }
  if (r.has("imu0")) {
    data::YamlOptionsReader i = r.child("imu0");
    const data::RigImu imu = data::readKalibrImuMap(i);
    i.finish();
    r.check(imu.intrinsics.isIdentity(), "imu0", "IMU intrinsics (Tw, Ta, Tg, ...) belong in a calibration file given with --calibration");
    o->imu_noise = imu.noise;
  }
}

}  // namespace adugs::data

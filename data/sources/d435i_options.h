#pragma once
// Options of the RealSense D435i live source (data/sources/d435i_source.h), defaults in code, read
// from the `d435i:` map of a run config (data/config/d435i.yaml, whose values are these).
// `adugs run` ignores the map; `adugs live --d435i` and `adugs record --d435i` use it.
#include <string>

#include "data/formats/kalibr_calibration.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::data {

struct D435iOptions {
  // Where the kernel shows the camera (tests point these at a fake tree).
  std::string sys_root = "/sys";
  std::string dev_root = "/dev";
  std::string usb_id = "8086:0b3a";  // vendor:product of the D435i
  std::string serial;                // USB serial number of the camera to use; "" = the first found
  // kernel: V4L2 + UVC + IIO (this project's own path, any Linux); librealsense: ViSP's
  // vpRealSense2 (only in builds whose ViSP has librealsense2, not Debian's).
  std::string backend = "kernel";

  // Images.
  std::string stream = "infrared";  // infrared (the left imager, global shutter) | color (rolling)
  std::string format = "auto";      // auto (GREY, else Y8I) | grey | y8i | yuyv
  int width = 848;
  int height = 480;
  double fps = 30;
  int buffers = 6;             // driver buffers: a consumer may fall this many frames behind
  bool metadata = true;        // device-clock stamps from the UVC metadata node when there is one
  std::string emitter = "off"; // off | on | keep: its dot pattern ruins tracking on infrared
  int exposure_us = 0;         // 0: auto exposure; otherwise manual, in microseconds
  int gain = 0;                // with manual exposure: the UVC gain (16..248); 0 keeps it

  // IMU (the HID accel_3d / gyro_3d IIO devices).
  bool imu = true;
  double accel_hz = 250;       // D435i: 63 or 250; newer units (BMI085): 100 or 200
  double gyro_hz = 400;        // 200 or 400
  double gyro_lsb_deg_s = 0;   // 0: from the data width (16-bit: 0.1, 32-bit: 0.0001 deg/s per LSB)
  int iio_buffer_records = 1024;

  // Time order of the merged stream: the longest a frame (after its mid-exposure stamp) or an IMU
  // sample (after its stamp) may take to arrive; the other stream waits this long at most.
  double frame_latency_s = 0.2;
  double imu_latency_s = 0.1;
  double stall_timeout_s = 5.0;  // no data from a stream for this long ends the source
  // The first measurements fit the device clock and are not handed out: the first clock pairs
  // may carry a start-up delay that later pairs correct by more than an IMU period.
  double clock_warmup_s = 0.5;

  // Calibration used when no Kalibr files are given (Kalibr spelling: cam0 / imu0 maps).
  // The defaults are a placeholder for the infrared camera (see data/config/d435i.yaml).
  data::RigCamera camera = placeholderCamera();
  data::ImuNoise imu_noise = defaultImuNoise();

  static data::RigCamera placeholderCamera();
  static data::ImuNoise defaultImuNoise();
};

// Reads the keys above (cam0: and imu0: as Kalibr maps) and checks them; call finish() after.
void readD435iOptions(data::YamlOptionsReader& reader, D435iOptions* options);

}  // namespace adugs::data

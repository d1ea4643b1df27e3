#pragma once
// A simulated RealSense D435i for the live-source tests, built from what the kernel shows of a
// real one: a sysfs tree in a temp folder (the USB device 8086:0b3a with its infrared, colour and
// metadata video4linux nodes and its HID accel_3d / gyro_3d IIO devices with scan elements; plus
// a laptop's own sensor hub and webcam as decoys), FIFOs as /dev/iio:deviceN, the fake V4L2 layer
// for the video nodes, and a device thread that runs in real time: a 32-bit microsecond counter
// (starting near its wrap, 50 ppm fast), gyro records at 400 Hz and accelerometer records at
// 250 Hz written to the FIFOs as the kernel lays them out, and 30 Hz frames (Y8I or GREY, as the
// code under test chose) with D4xx metadata (readout-start PTS, mid-exposure sensor timestamp).
//
// The samples encode what they are, so tests can check the delivered stream against the truth:
//   gyro k     raw counts (k mod 30000, 300, -450), device time t0 + 2500 k us
//   accel j    raw counts (j, 0, -1000) (1 g down the raw z axis: lying on its back), t0 + 4000 j us
//   frame f    mid-exposure at device time t0 + 10000 + 33333 f us; left image (or colour luma)
//              pixel (0,0) = f mod 256, (0,1) = f / 256, the rest 100; right image 200 everywhere,
//              colour chroma 128 (grey)
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>

#include "data/sources/d435i_options.h"
#include "tests/data/live/fake_v4l2.h"

namespace adugs::test {

struct FakeD435iConfig {
  int gyro_bits = 16;             // 16: firmware before 5.16; 32: 5.16 and later
  int accel_bits = 16;
  bool metadata_node = true;      // the infrared node has its metadata node
  bool d4xx_metadata = true;      // D4XX format with capture timing (false: plain UVCH header)
  bool metadata_silent = false;   // the metadata node streams but never fills a buffer
  bool imu_device_stamps = true;  // IIO timestamps from the device (false: host CLOCK_REALTIME)
  uint32_t device_start_us = 0xFFFFFFFFu - 1'500'000;  // the counter wraps 1.5 s in
  double drift = 50e-6;           // the device clock runs this much fast
  int exposure_us = 8000;
  int readout_us = 10000;
  int imu_latency_us = 1000;      // record written this long after its sample
  // The camera at rest in front of a textured wall (for the pipeline tests): gyro (0, 0, 0), accel
  // (0, 0, -1000) (1 g), the left image a fixed pattern of random grey 24-pixel cells with 0-4
  // grey levels of noise per frame (pixels (0,0) and (0,1) still hold the frame index).
  bool still_textured_scene = false;
};

class FakeD435i {
 public:
  FakeD435i(const std::filesystem::path& root, const FakeD435iConfig& config = {});
  ~FakeD435i();

  FakeV4l2& v4l2() { return v4l2_; }
  // Options pointing at the fake tree (everything else default).
  data::D435iOptions options() const;
  std::string sysRoot() const { return (root_ / "sys").string(); }
  std::string devRoot() const { return (root_ / "dev").string(); }
  std::filesystem::path iioDir(const std::string& name) const;  // "accel_3d" / "gyro_3d"

  // Starts the device thread (call after the source opened the device files).
  void start();
  // The IMU goes away (its FIFOs close) / the camera goes away (its nodes return ENODEV); the
  // thread stops producing.
  void unplugImu();
  void unplugCamera();
  void stop();

  // Truth: the counter is device_start_us at host time start_host_ns and runs (1 + drift) fast.
  int64_t startHostNs() const { return start_host_ns_; }
  double hostNsOfDeviceUs(int64_t device_us_unwrapped) const;
  int64_t deviceStartUs() const { return config_.device_start_us; }
  int framesDelivered() const { return frames_.load(); }
  int gyroWritten() const { return gyro_.load(); }

 private:
  void buildTree();
  void run();
  void writeRecord(int fd, int32_t x, int32_t y, int32_t z, int64_t stamp_ns, int bits);
  void deliverFrame(int index);

  std::filesystem::path root_;
  FakeD435iConfig config_;
  FakeV4l2 v4l2_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> imu_gone_{false}, camera_gone_{false};
  std::atomic<int> frames_{0}, gyro_{0};
  int64_t start_host_ns_ = 0;
};

}  // namespace adugs::test

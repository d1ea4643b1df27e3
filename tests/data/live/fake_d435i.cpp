#include "tests/data/live/fake_d435i.h"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <ctime>

#include <csignal>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/stat.h>
#include <unistd.h>

#include "data/device/host_clock.h"
#include "tests/device_bytes.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace fs = std::filesystem;
namespace {

const char* kUsbPath = "devices/pci0000:00/0000:00:14.0/usb2/2-1";

int64_t nowNs(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleepUntil(int64_t host_ns) {
  timespec ts{static_cast<time_t>(host_ns / 1'000'000'000), static_cast<long>(host_ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

void link(const fs::path& at, const std::string& target) {
  fs::create_directories(at.parent_path());
  fs::create_directory_symlink(target, at);
}

void iioDevice(const fs::path& sys, const fs::path& dir, const std::string& name, const std::string& type, int bits) {
  writeText(dir / "name", name + "\n");
  const std::string axis_type = "le:s" + std::to_string(bits) + "/32>>0\n";
  int index = 0;
  for (const char* axis : {"x", "y", "z"}) {
    const std::string base = "scan_elements/in_" + type + "_" + axis;
    writeText(dir / (base + "_en"), "0\n");
    writeText(dir / (base + "_index"), std::to_string(index++) + "\n");
    writeText(dir / (base + "_type"), axis_type);
  }
  writeText(dir / "scan_elements/in_timestamp_en", "0\n");
  writeText(dir / "scan_elements/in_timestamp_index", "3\n");
  writeText(dir / "scan_elements/in_timestamp_type", "le:s64/64>>0\n");
  writeText(dir / ("in_" + type + "_sampling_frequency"), "0\n");
  writeText(dir / ("in_" + type + "_scale"), type == "accel" ? "0.009806650\n" : "0.000174532\n");
  writeText(dir / ("in_" + type + "_hysteresis"), "0\n");
  writeText(dir / "buffer/length", "2\n");
  writeText(dir / "buffer/enable", "0\n");
  writeText(dir / "trigger/current_trigger", "\n");
  writeText(dir / "current_timestamp_clock", "realtime\n");
  const std::string node = dir.filename().string();
  link(sys / "bus/iio/devices" / node, "../../../" + fs::relative(dir, sys).string());
}

void videoNode(const fs::path& sys, const fs::path& interface, const std::string& node, int index) {
  const fs::path dir = interface / "video4linux" / node;
  writeText(dir / "index", std::to_string(index) + "\n");
  writeText(dir / "name", "Intel(R) RealSense(TM) Depth Ca\n");
  link(dir / "device", "../../../" + interface.filename().string());
  link(sys / "class/video4linux" / node, "../../" + fs::relative(dir, sys).string());
}

}  // namespace

FakeD435i::FakeD435i(const fs::path& root, const FakeD435iConfig& config) : root_(root), config_(config) {
  // The code under test may close the device files while the device thread still writes: a
  // write error then, not a signal that ends the test process.
  std::signal(SIGPIPE, SIG_IGN);
  buildTree();
  const std::vector<FakeFrameSize> depth_sizes = {
      {640, 480, {6, 15, 30, 60, 90}}, {848, 480, {6, 15, 30, 60, 90}}, {1280, 720, {6, 15, 30}}};
  v4l2_.addVideoNode(devRoot() + "/video0", {{v4l2_fourcc('Z', '1', '6', ' '), "16-bit Depth", depth_sizes},
                                             {v4l2_fourcc('G', 'R', 'E', 'Y'), "8-bit Greyscale", depth_sizes},
                                             {v4l2_fourcc('Y', '8', 'I', ' '), "Interleaved 8-bit Greyscale", depth_sizes}});
  if (config.metadata_node) {
    if (config.d4xx_metadata)
      v4l2_.addMetaNode(devRoot() + "/video1", {v4l2_fourcc('D', '4', 'X', 'X'), v4l2_fourcc('U', 'V', 'C', 'H')});
    else
      v4l2_.addMetaNode(devRoot() + "/video1", {v4l2_fourcc('U', 'V', 'C', 'H')});
  }
  v4l2_.addVideoNode(devRoot() + "/video2", {{v4l2_fourcc('Y', 'U', 'Y', 'V'), "YUYV 4:2:2",
                                              {{640, 480, {15, 30, 60}}, {848, 480, {15, 30, 60}}, {1280, 720, {15, 30}}}}});
  v4l2_.addMetaNode(devRoot() + "/video3", {v4l2_fourcc('D', '4', 'X', 'X'), v4l2_fourcc('U', 'V', 'C', 'H')});
  v4l2_.addVideoNode(devRoot() + "/video4", {{v4l2_fourcc('Y', 'U', 'Y', 'V'), "YUYV 4:2:2", {{640, 480, {30}}}}},
                     "Integrated Camera");
}

FakeD435i::~FakeD435i() { stop(); }

void FakeD435i::buildTree() {
  const fs::path sys = root_ / "sys";
  const fs::path usb = sys / kUsbPath;
  writeText(usb / "idVendor", "8086\n");
  writeText(usb / "idProduct", "0b3a\n");
  writeText(usb / "serial", "843112071234\n");
  writeText(usb / "product", "Intel(R) RealSense(TM) Depth Camera 435i\n");
  writeText(usb / "speed", "5000\n");
  videoNode(sys, usb / "2-1:1.0", "video0", 0);
  if (config_.metadata_node) videoNode(sys, usb / "2-1:1.0", "video1", 1);
  videoNode(sys, usb / "2-1:1.3", "video2", 0);
  videoNode(sys, usb / "2-1:1.3", "video3", 1);
  const fs::path hid = usb / "2-1:1.5/0003:8086:0B3A.0004";
  iioDevice(sys, hid / "HID-SENSOR-200073.3.auto/iio:device1", "accel_3d", "accel", config_.accel_bits);
  iioDevice(sys, hid / "HID-SENSOR-200076.4.auto/iio:device2", "gyro_3d", "anglvel", config_.gyro_bits);
  // Decoys: a laptop's sensor hub (an accel_3d of its own) and its webcam.
  const fs::path hub = sys / "devices/pci0000:00/0000:00:14.0/usb1/1-3";
  writeText(hub / "idVendor", "8087\n");
  writeText(hub / "idProduct", "0a1e\n");
  iioDevice(sys, hub / "1-3:1.0/0003:8087:0A1E.0001/HID-SENSOR-200073.1.auto/iio:device0", "accel_3d", "accel", 16);
  const fs::path webcam = sys / "devices/pci0000:00/0000:00:14.0/usb1/1-4";
  writeText(webcam / "idVendor", "04f2\n");
  writeText(webcam / "idProduct", "b6dd\n");
  videoNode(sys, webcam / "1-4:1.0", "video4", 0);
  fs::create_directories(root_ / "dev");
  for (const char* fifo : {"iio:device0", "iio:device1", "iio:device2"})
    if (mkfifo((root_ / "dev" / fifo).c_str(), 0600) != 0) throw std::runtime_error("mkfifo failed");
}

fs::path FakeD435i::iioDir(const std::string& name) const {
  const fs::path hid = root_ / "sys" / kUsbPath / "2-1:1.5/0003:8086:0B3A.0004";
  return name == "accel_3d" ? hid / "HID-SENSOR-200073.3.auto/iio:device1" : hid / "HID-SENSOR-200076.4.auto/iio:device2";
}

data::D435iOptions FakeD435i::options() const {
  data::D435iOptions o;
  o.sys_root = sysRoot();
  o.dev_root = devRoot();
  return o;
}

double FakeD435i::hostNsOfDeviceUs(int64_t device_us) const {
  return static_cast<double>(start_host_ns_) +
         static_cast<double>(device_us - static_cast<int64_t>(config_.device_start_us)) * 1000.0 / (1.0 + config_.drift);
}

void FakeD435i::start() {
  start_host_ns_ = nowNs(CLOCK_MONOTONIC) + 20'000'000;
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void FakeD435i::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void FakeD435i::unplugImu() { imu_gone_ = true; }

void FakeD435i::unplugCamera() {
  camera_gone_ = true;
  v4l2_.unplug(devRoot() + "/video0");
  if (config_.metadata_node) v4l2_.unplug(devRoot() + "/video1");
}

void FakeD435i::writeRecord(int fd, int32_t x, int32_t y, int32_t z, int64_t stamp_ns, int bits) {
  const std::vector<uint8_t> r = hidImuRecord(x, y, z, stamp_ns, bits / 8);
  size_t done = 0;
  while (done < r.size()) {
    const ssize_t n = ::write(fd, r.data() + done, r.size() - done);
    if (n < 0 && errno == EAGAIN) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));  // the reader is behind: wait
      continue;
    }
    if (n <= 0) return;
    done += static_cast<size_t>(n);
  }
}

void FakeD435i::deliverFrame(int f) {
  // The infrared node, or the colour node if that is the one streaming.
  const bool colour = v4l2_.state(devRoot() + "/video2").streaming;
  const std::string video = devRoot() + (colour ? "/video2" : "/video0");
  const std::string meta = devRoot() + (colour ? "/video3" : "/video1");
  const FakeV4l2::State s = v4l2_.state(video);
  const int64_t t0 = config_.device_start_us;
  const int64_t mid = t0 + 10000 + 33333LL * f;
  const int64_t readout_start = mid + config_.exposure_us / 2;
  const double arrival = hostNsOfDeviceUs(readout_start) + 300'000.0;  // first packet 0.3 ms after
  if ((config_.metadata_node || colour) && !config_.metadata_silent) {
    D4xxMetadataFields m;
    m.host_ns = static_cast<uint64_t>(std::llround(arrival));
    m.pts_us = static_cast<uint32_t>(readout_start);  // the counter's 32 bits
    m.capture_timing = v4l2_.state(meta).meta_format == v4l2_fourcc('D', '4', 'X', 'X');
    m.frame_counter = static_cast<uint32_t>(f);
    m.sensor_timestamp_us = static_cast<uint32_t>(mid);
    m.exposure_us = static_cast<uint32_t>(config_.exposure_us);
    m.readout_us = static_cast<uint32_t>(config_.readout_us);
    m.frame_interval_us = 33333;
    v4l2_.deliver(meta, d4xxMetadataBlock(m), std::llround(arrival));
  }
  // GREY: 100 everywhere; Y8I: left 100, right 200; YUYV: luma 100, chroma 128 (grey). The first
  // two (left / luma) pixels hold the frame index.
  const bool one_byte = s.fourcc == v4l2_fourcc('G', 'R', 'E', 'Y');
  const int bpp = one_byte ? 1 : 2;
  std::vector<uint8_t> image(static_cast<size_t>(s.width) * s.height * bpp, 0);
  for (size_t i = 0; i < image.size(); i += bpp) {
    image[i] = 100;
    if (bpp == 2) image[i + 1] = colour ? 128 : 200;
  }
  if (config_.still_textured_scene) {
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        uint32_t cell = static_cast<uint32_t>((y / 24) * 1000 + x / 24) * 2654435761u;  // a hash per cell
        cell ^= cell >> 13;
        uint32_t noise = ((static_cast<uint32_t>(f) * 7919u + static_cast<uint32_t>(y)) * 104729u +  // sensor noise
                           static_cast<uint32_t>(x)) *
                          2246822519u;  // unsigned: wraps by definition (int overflowed: UB)
        noise ^= noise >> 15;
        image[(static_cast<size_t>(y) * s.width + x) * bpp] = static_cast<uint8_t>(30 + cell % 200 + noise % 5);
      }
  }
  image[0] = static_cast<uint8_t>(f & 0xff);
  image[bpp] = static_cast<uint8_t>((f >> 8) & 0xff);
  v4l2_.deliver(video, image, std::llround(arrival));
  ++frames_;
}

void FakeD435i::run() {
  // Writers for the IIO FIFOs: the code under test opened them for reading already.
  int accel_fd = -1, gyro_fd = -1;
  for (int attempt = 0; attempt < 200 && (accel_fd < 0 || gyro_fd < 0); ++attempt) {
    if (accel_fd < 0) accel_fd = ::open((root_ / "dev/iio:device1").c_str(), O_WRONLY | O_NONBLOCK);
    if (gyro_fd < 0) gyro_fd = ::open((root_ / "dev/iio:device2").c_str(), O_WRONLY | O_NONBLOCK);
    if (accel_fd < 0 || gyro_fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const int64_t t0 = config_.device_start_us;
  const int64_t realtime_offset = data::clockMinusMonotonicNs(CLOCK_REALTIME);
  int64_t k = 0, j = 0, f = 0;
  const auto imuStamp = [&](int64_t device_us) {
    if (config_.imu_device_stamps) return (device_us & 0xFFFFFFFFLL) * 1000;  // the kernel's ns of the us counter
    return std::llround(hostNsOfDeviceUs(device_us)) + realtime_offset;
  };
  while (running_) {
    // The next event of each stream, by its delivery time on the host.
    const double gyro_at = hostNsOfDeviceUs(t0 + 2500 * k) + config_.imu_latency_us * 1000.0;
    const double accel_at = hostNsOfDeviceUs(t0 + 4000 * j) + config_.imu_latency_us * 1000.0;
    const double frame_at = hostNsOfDeviceUs(t0 + 10000 + 33333 * f + config_.exposure_us / 2 + config_.readout_us);
    const double at = std::min({gyro_at, accel_at, frame_at});
    sleepUntil(std::llround(at));
    if (!running_) break;
    if (at == gyro_at) {
      const bool still = config_.still_textured_scene;
      if (!imu_gone_ && gyro_fd >= 0)
        writeRecord(gyro_fd, still ? 0 : static_cast<int32_t>(k % 30000), still ? 0 : 300, still ? 0 : -450,
                    imuStamp(t0 + 2500 * k), config_.gyro_bits);
      ++k;
      ++gyro_;
    } else if (at == accel_at) {
      if (!imu_gone_ && accel_fd >= 0)
        writeRecord(accel_fd, config_.still_textured_scene ? 0 : static_cast<int32_t>(j), 0, -1000,
                    imuStamp(t0 + 4000 * j), config_.accel_bits);
      ++j;
    } else {
      if (!camera_gone_) deliverFrame(static_cast<int>(f));
      ++f;
    }
    if (imu_gone_ && accel_fd >= 0) {
      ::close(accel_fd);
      ::close(gyro_fd);
      accel_fd = gyro_fd = -1;
    }
  }
  if (accel_fd >= 0) ::close(accel_fd);
  if (gyro_fd >= 0) ::close(gyro_fd);
}

}  // namespace adugs::test

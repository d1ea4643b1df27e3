#include "data/sources/d435i_probe.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <unistd.h>

#include "data/device/camera_nodes.h"
#include "data/device/d4xx_controls.h"
#include "data/device/iio_sensor.h"
#include "data/device/pixel_formats.h"
#include "data/device/realsense_imu.h"
#include "data/device/usb_device_tree.h"
#include "data/input_error.h"
#include "data/sources/d435i_source.h"

namespace adugs::data {
namespace {

std::string access(const std::string& path, int mode) {
  if (::access(path.c_str(), F_OK) != 0) return "missing";
  return ::access(path.c_str(), mode) == 0 ? "ok" : "permission denied (udev rule / groups: README)";
}

std::string rates(const V4l2FrameSize& z) {
  std::ostringstream s;
  s << z.width << "x" << z.height;
  if (!z.rates_hz.empty()) {
    s << " (";
    for (size_t k = 0; k < z.rates_hz.size(); ++k) s << (k ? "/" : "") << z.rates_hz[k];
    s << " Hz)";
  }
  return s.str();
}

void printNodes(std::ostream& out, const std::vector<VideoNodeInfo>& nodes) {
  for (const VideoNodeInfo& n : nodes) {
    out << "  " << n.node.dev_path << "  ";
    if (!n.opened) {
      out << n.error << "\n";
      continue;
    }
    out << (n.video ? "video capture" : n.meta ? "metadata" : "other") << ", " << n.driver << " \"" << n.card << "\", interface "
        << std::filesystem::path(n.node.interface).filename().string() << ", access "
        << access(n.node.dev_path, R_OK | W_OK) << "\n";
    if (n.meta) {
      out << "      formats:";
      for (const V4l2FormatInfo& f : n.formats) out << " " << data::fourccText(f.fourcc);
      out << "\n";
      continue;
    }
    for (const V4l2FormatInfo& f : n.formats) {
      out << "      " << std::left << std::setw(5) << data::fourccText(f.fourcc) << std::right << " " << f.description << ":";
      for (size_t i = 0; i < f.sizes.size(); ++i) out << (i ? ", " : " ") << rates(f.sizes[i]);
      out << "\n";
    }
  }
}

void printControls(std::ostream& out, V4l2Io& io, const std::string& path) {
  try {
    V4l2Stream s(io, path);
    D4xxControls c(io, s.fd(), path);
    uint8_t emitter = 0;
    bool ae = false;
    uint32_t exposure = 0;
    int gain = 0;
    out << "  controls of " << path << " (UVC extension unit 3):";
    static const char* kModes[] = {"off", "laser", "laser auto", "LED"};
    if (c.readEmitter(&emitter)) out << " emitter " << int(emitter) << " (" << (emitter < 4 ? kModes[emitter] : "?") << ")";
    else out << " emitter unreadable";
    if (c.readAutoExposure(&ae)) out << ", auto exposure " << (ae ? "on" : "off");
    if (c.readExposureUs(&exposure)) out << ", exposure " << exposure << " us";
    if (c.readGain(&gain)) out << ", gain " << gain;
    out << "\n";
    if (!c.error().empty()) out << "      (" << c.error() << ")\n";
  } catch (const data::InputError& e) {
    out << "  controls: " << e.what() << "\n";
  }
}

void printIio(std::ostream& out, const UsbIioDevice& d) {
  const std::string type = d.name == "gyro_3d" ? "anglvel" : d.name == "accel_3d" ? "accel" : "";
  out << "  " << d.dev_path << "  " << d.name << ", " << d.sys_dir << ", access " << access(d.dev_path, R_OK) << "\n";
  try {
    const IioDeviceInfo info = readIioDeviceInfo(d, type);
    for (size_t i = 0; i < info.channels.size(); ++i) {
      const data::IioChannel& c = info.channels[i];
      const data::IioScanType& t = c.type;
      out << "      " << std::left << std::setw(12) << c.name << std::right << " index " << c.index << ", "
          << (t.big_endian ? "be" : "le") << ":" << (t.is_signed ? 's' : 'u') << t.real_bits << "/" << t.storage_bits
          << (t.repeat > 1 ? "X" + std::to_string(t.repeat) : std::string()) << ">>" << t.shift
          << (info.enabled[i] ? ", enabled" : "") << "\n";
    }
    out << "      sampling frequency: "
        << (info.sampling_frequency_file.empty() ? "no file" : info.sampling_frequency + " Hz (" + info.sampling_frequency_file + ")");
    if (!info.sampling_frequency_available.empty()) out << ", available " << info.sampling_frequency_available;
    out << "; kernel scale " << (info.scale.empty() ? "-" : info.scale) << "; hysteresis "
        << (info.hysteresis.empty() ? "-" : info.hysteresis) << "; timestamp clock "
        << (info.timestamp_clock.empty() ? "-" : info.timestamp_clock) << "\n";
    for (const data::IioChannel& c : info.channels) {
      if (c.name == "anglvel_x") {
        const double lsb = data::realsenseGyroLsbDegPerSec(c.type.real_bits);
        out << "      gyro data " << c.type.real_bits << "-bit: "
            << (lsb > 0 ? std::to_string(lsb) + " deg/s per LSB (firmware " + (c.type.real_bits == 16 ? "before" : "5.16 or") +
                              (c.type.real_bits == 16 ? " 5.16)" : " later)")
                        : std::string("unknown firmware: set d435i.gyro_lsb_deg_s"))
            << "\n";
      }
      if (c.name == "accel_x") out << "      accel data " << c.type.real_bits << "-bit: 0.001 g per LSB\n";
    }
  } catch (const data::InputError& e) {
    out << "      " << e.what() << "\n";
  }
}

}  // namespace

void printD435iInfo(std::ostream& out, const D435iOptions& options, V4l2Io& io) {
  const std::vector<UsbCamera> cameras = findUsbCameras(options.sys_root, options.dev_root, options.usb_id);
  if (cameras.empty()) {
    std::string seen;
    for (const UsbCamera& c : findUsbCameras(options.sys_root, options.dev_root, ""))
      seen += " " + c.vendor_id + ":" + c.product_id + (c.product.empty() ? "" : " (" + c.product + ")");
    throw data::InputError(options.sys_root + "/class/video4linux", 0, "d435i.usb_id",
                           "no USB camera " + options.usb_id + " with a V4L2 node; USB video devices seen:" +
                               (seen.empty() ? std::string(" none") : seen));
  }
  for (const UsbCamera& cam : cameras) {
    out << "USB " << cam.vendor_id << ":" << cam.product_id << " \"" << cam.product << "\" serial "
        << (cam.serial.empty() ? "?" : cam.serial) << " at " << cam.bus_port << " (" << (cam.speed.empty() ? "?" : cam.speed)
        << " Mb/s" << (!cam.speed.empty() && std::atof(cam.speed.c_str()) < 5000 ? ": USB 2, use a USB 3 port" : "") << ")\n";
    const std::vector<VideoNodeInfo> nodes = inspectVideoNodes(io, cam);
    printNodes(out, nodes);
    const D4xxNodes chosen = selectD4xxNodes(nodes, "infrared");
    if (chosen.video >= 0) printControls(out, io, nodes[static_cast<size_t>(chosen.video)].node.dev_path);
    if (cam.iio.empty()) out << "  no IIO devices under this camera (no IMU, or no hid-sensor drivers)\n";
    for (const UsbIioDevice& d : cam.iio) printIio(out, d);
    const D4xxNodes used = selectD4xxNodes(nodes, options.stream);
    out << "  the options would use: " << options.stream << " "
        << (used.video >= 0 ? nodes[static_cast<size_t>(used.video)].node.dev_path : std::string("(none found)"));
    if (used.meta >= 0) out << " + metadata " << nodes[static_cast<size_t>(used.meta)].node.dev_path;
    out << ", " << options.width << "x" << options.height << " at " << options.fps << " Hz";
    if (options.imu) out << "; IMU accel " << options.accel_hz << " Hz, gyro " << options.gyro_hz << " Hz";
    out << "\n";
  }
}

void printD435iStreamCheck(std::ostream& out, const D435iOptions& options, double seconds, V4l2Io& io) {
  D435iSource source(options, io);
  out << "streaming " << seconds << " s: " << source.description() << "\n";
  std::vector<int64_t> frames, imu;
  data::Measurement m;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until && source.next(m)) (m.isFrame() ? frames : imu).push_back(m.timeNs());
  const auto rate = [](const std::vector<int64_t>& t) {
    return t.size() < 2 ? 0.0 : (t.size() - 1) / (1e-9 * static_cast<double>(t.back() - t.front()));
  };
  const auto gaps = [](const std::vector<int64_t>& t) {
    std::vector<double> d;
    for (size_t i = 1; i < t.size(); ++i) d.push_back(1e-6 * static_cast<double>(t[i] - t[i - 1]));
    std::sort(d.begin(), d.end());
    std::ostringstream s;
    if (!d.empty()) s << "interval min " << d.front() << " / median " << d[d.size() / 2] << " / max " << d.back() << " ms";
    return s.str();
  };
  const D435iStats st = source.stats();
  out << "  frames " << frames.size() << " (" << std::setprecision(4) << rate(frames) << " Hz, " << gaps(frames) << ")\n";
  out << "  IMU    " << imu.size() << " united samples (" << rate(imu) << " Hz, " << gaps(imu) << "); read "
      << st.accel_samples << " accel, " << st.gyro_samples << " gyro\n";
  out << "  lost: " << st.frames_lost_by_driver << " frames by the driver, " << st.frames_without_metadata
      << " without metadata, " << st.frames_bad << " bad, " << st.frames_late << " late; IMU " << st.imu_late << " late, "
      << st.imu_out_of_order << " out of order, " << st.gyro_unmatched << " gyro unmatched\n";
  out << "  clock: frames " << (st.device_clock ? "on the camera clock (metadata)" : "host-stamped (no metadata)")
      << ", IMU " << (st.imu_device_stamps ? "on the camera clock" : "host-stamped") << ", camera clock drift "
      << st.clock_drift_ppm << " ppm\n";
  if (!source.stopReason().empty()) out << "  stopped: " << source.stopReason() << "\n";
}

}  // namespace adugs::data

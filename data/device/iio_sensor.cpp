#include "data/device/iio_sensor.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fcntl.h>
#include <unistd.h>

#include "data/input_error.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

bool readText(const fs::path& file, std::string* text) {
  std::ifstream in(file);
  if (!in) return false;
  std::getline(in, *text);
  while (!text->empty() && (text->back() == '\n' || text->back() == ' ')) text->pop_back();
  return true;
}

std::string requireText(const fs::path& file) {
  std::string text;
  if (!readText(file, &text))
    throw data::InputError(file.string(), 0, "", std::string("cannot read: ") + std::strerror(errno));
  return text;
}

// The sampling frequency file of channel type `type`: in_<type>_sampling_frequency, else a
// shared sampling_frequency, else any other *sampling_frequency (as librealsense looks for it).
std::string samplingFrequencyFile(const fs::path& dir, const std::string& type) {
  for (const std::string& name : {"in_" + type + "_sampling_frequency", std::string("sampling_frequency")})
    if (fs::exists(dir / name)) return name;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.find("sampling_frequency") != std::string::npos && name.find("available") == std::string::npos) return name;
  }
  return "";
}

}  // namespace

IioDeviceInfo readIioDeviceInfo(const UsbIioDevice& device, const std::string& type) {
  IioDeviceInfo info;
  const fs::path dir(device.sys_dir);
  info.name = device.name;
  const fs::path scan = dir / "scan_elements";
  std::error_code ec;
  if (!fs::is_directory(scan, ec)) throw data::InputError(scan.string(), 0, "", "no scan elements: not a buffered IIO device");
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(scan, ec)) {
    const std::string file = e.path().filename().string();
    if (file.rfind("in_", 0) == 0 && file.size() > 6 && file.compare(file.size() - 3, 3, "_en") == 0)
      names.push_back(file.substr(3, file.size() - 6));
  }
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    data::IioChannel c;
    c.name = name;
    const fs::path type_file = scan / ("in_" + name + "_type");
    c.type = data::parseIioScanType(requireText(type_file), type_file.string());
    const fs::path index_file = scan / ("in_" + name + "_index");
    const std::string index = requireText(index_file);
    try {
      size_t used = 0;
      c.index = std::stoi(index, &used);
      if (used != index.size()) throw std::invalid_argument(index);
    } catch (const std::exception&) {
      throw data::InputError(index_file.string(), 0, "index", "'" + index + "' is not a number");
    }
    info.channels.push_back(c);
    info.enabled.push_back(requireText(scan / ("in_" + name + "_en")) == "1");
  }
  info.sampling_frequency_file = samplingFrequencyFile(dir, type);
  if (!info.sampling_frequency_file.empty()) {
    readText(dir / info.sampling_frequency_file, &info.sampling_frequency);
    readText(dir / (info.sampling_frequency_file + "_available"), &info.sampling_frequency_available);
  }
  readText(dir / ("in_" + type + "_scale"), &info.scale);
  readText(dir / ("in_" + type + "_hysteresis"), &info.hysteresis);
  readText(dir / "current_timestamp_clock", &info.timestamp_clock);
  return info;
}

IioSensor::IioSensor(const UsbIioDevice& device, const std::string& type, double rate_hz, int buffer_records)
    : device_(device), type_(type) {
  const IioDeviceInfo info = readIioDeviceInfo(device, type);
  // Streaming off while the scan is changed (a previous run may have left it on).
  writeAttribute("buffer/enable", "0", true);
  const std::string wanted[4] = {type + "_x", type + "_y", type + "_z", "timestamp"};
  for (const data::IioChannel& c : info.channels) {
    const bool want = std::find(std::begin(wanted), std::end(wanted), c.name) != std::end(wanted);
    writeAttribute("scan_elements/in_" + c.name + "_en", want ? "1" : "0", true);
    if (want) channels_.push_back(c);
  }
  record_bytes_ = data::layoutIioRecord(&channels_, device.sys_dir);
  for (int i = 0; i < 4; ++i) {
    size_t k = 0;
    while (k < channels_.size() && channels_[k].name != wanted[i]) ++k;
    if (k == channels_.size())
      throw data::InputError(device.sys_dir + "/scan_elements", 0, "in_" + wanted[i] + "_en",
                             "missing: the device '" + device.name + "' has no " + wanted[i] + " scan element");
    if (i < 3) axis_[i] = k;
    else timestamp_ = k;
  }
  if (!info.sampling_frequency_file.empty()) {
    if (rate_hz > 0) writeAttribute(info.sampling_frequency_file, std::to_string(static_cast<int>(rate_hz + 0.5)), true);
    std::string now;
    if (readText(fs::path(device.sys_dir) / info.sampling_frequency_file, &now)) rate_hz_ = std::atof(now.c_str());
  }
  // The HID driver's trigger, as librealsense sets it (its asynchronous set-up may leave it unset).
  std::string trigger;
  if (readText(fs::path(device.sys_dir) / "trigger/current_trigger", &trigger) && trigger.empty()) {
    const std::string number = fs::path(device.sys_dir).filename().string().substr(std::strlen("iio:device"));
    writeAttribute("trigger/current_trigger", device.name + "-dev" + number, false);
  }
  // Host stamps, if the kernel stamps records itself, on the realtime clock: about 1.7e18 ns, far
  // from any device counter (< 2^32 us), which a monotonic clock of a young host is not.
  writeAttribute("current_timestamp_clock", "realtime", false);
  readText(fs::path(device.sys_dir) / "current_timestamp_clock", &host_stamp_clock_);
  writeAttribute("buffer/length", std::to_string(buffer_records), false);
  writeAttribute("buffer/enable", "1", true);
  buffer_enabled_ = true;
  fd_ = ::open(device.dev_path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    writeAttribute("buffer/enable", "0", false);
    buffer_enabled_ = false;
    throw data::InputError(device.dev_path, 0, "", std::string("cannot open: ") + std::strerror(err) +
                                                       (err == EACCES ? " (install the udev rule: README, \"Live on a D435i\")" : ""));
  }
}

IioSensor::~IioSensor() {
  if (fd_ >= 0) ::close(fd_);
  if (buffer_enabled_) {
    try {
      writeAttribute("buffer/enable", "0", false);
    } catch (...) {
    }
  }
}

void IioSensor::writeAttribute(const std::string& relative, const std::string& value, bool required) {
  const fs::path file = fs::path(device_.sys_dir) / relative;
  std::ofstream out(file);
  if (out) out << value << "\n";
  if (out && out.flush()) return;
  if (required)
    throw data::InputError(file.string(), 0, "", "cannot write '" + value + "': " + std::strerror(errno) +
                                                     (errno == EACCES ? " (install the udev rule: README, \"Live on a D435i\")" : ""));
}

bool IioSensor::read(std::vector<IioSample>* out) {
  if (gone_) return false;
  uint8_t chunk[4096];
  for (;;) {
    const ssize_t n = ::read(fd_, chunk, sizeof(chunk));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
    if (n <= 0) {
      gone_ = true;
      message_ = device_.dev_path + " (" + device_.name + "): " +
                 (n == 0 ? std::string("the device closed") : std::string(std::strerror(errno))) +
                 (n == 0 || errno == ENODEV ? " (camera unplugged?)" : "");
      return false;
    }
    pending_.insert(pending_.end(), chunk, chunk + n);
    size_t offset = 0;
    while (pending_.size() - offset >= record_bytes_) {
      const uint8_t* record = pending_.data() + offset;
      IioSample s;
      for (int i = 0; i < 3; ++i) s.counts[i] = static_cast<double>(data::decodeIioValue(record, channels_[axis_[i]]));
      s.timestamp_ns = data::decodeIioValue(record, channels_[timestamp_]);
      out->push_back(s);
      offset += record_bytes_;
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(offset));
    if (static_cast<size_t>(n) < sizeof(chunk)) return true;
  }
}

}  // namespace adugs::data

#include "data/device/usb_device_tree.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

std::string readLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The nearest ancestor of `dir` (itself included) that is a USB device, or "" below sys_root.
fs::path usbDeviceOf(const fs::path& dir, const fs::path& sys_root) {
  std::error_code ec;
  fs::path p = fs::canonical(dir, ec);
  if (ec) return {};
  const fs::path root = fs::canonical(sys_root, ec);
  while (!p.empty() && p != p.root_path() && p != root) {
    if (fs::exists(p / "idVendor") && fs::exists(p / "idProduct")) return p;
    p = p.parent_path();
  }
  return {};
}

bool idMatches(const std::string& vendor, const std::string& product, const std::string& id) {
  if (id.empty()) return true;
  const std::string want = lower(id);
  const size_t colon = want.find(':');
  if (colon == std::string::npos) return vendor == want;
  return vendor == want.substr(0, colon) && product == want.substr(colon + 1);
}

int numberAfter(const std::string& name, const std::string& prefix) {
  if (name.rfind(prefix, 0) != 0) return -1;
  try {
    return std::stoi(name.substr(prefix.size()));
  } catch (...) {
    return -1;
  }
}

}  // namespace

std::vector<UsbCamera> findUsbCameras(const std::string& sys_root, const std::string& dev_root, const std::string& id) {
  std::map<std::string, UsbCamera> cameras;  // by USB sysfs directory
  std::error_code ec;
  const fs::path video_class = fs::path(sys_root) / "class" / "video4linux";
  if (fs::is_directory(video_class, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(video_class, ec)) {
      const std::string name = e.path().filename().string();
      if (numberAfter(name, "video") < 0) continue;
      const fs::path usb = usbDeviceOf(e.path(), sys_root);
      if (usb.empty()) continue;
      const std::string vendor = lower(readLine(usb / "idVendor")), product = lower(readLine(usb / "idProduct"));
      if (!idMatches(vendor, product, id)) continue;
      UsbCamera& cam = cameras[usb.string()];
      if (cam.usb_dir.empty()) {
        cam.usb_dir = usb.string();
        cam.bus_port = usb.filename().string();
        cam.vendor_id = vendor;
        cam.product_id = product;
        cam.serial = readLine(usb / "serial");
        cam.product = readLine(usb / "product");
        cam.speed = readLine(usb / "speed");
      }
      UsbVideoNode node;
      node.name = name;
      node.dev_path = (fs::path(dev_root) / name).string();
      const fs::path interface = fs::canonical(e.path() / "device", ec);
      node.interface = ec ? std::string() : interface.string();
      const std::string index = readLine(e.path() / "index");
      node.index = index.empty() ? -1 : std::atoi(index.c_str());
      cam.video.push_back(node);
    }
  }
  const fs::path iio_bus = fs::path(sys_root) / "bus" / "iio" / "devices";
  if (fs::is_directory(iio_bus, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(iio_bus, ec)) {
      const std::string name = e.path().filename().string();
      if (numberAfter(name, "iio:device") < 0) continue;
      const auto it = cameras.find(usbDeviceOf(e.path(), sys_root).string());
      if (it == cameras.end()) continue;
      it->second.iio.push_back({readLine(e.path() / "name"), e.path().string(), (fs::path(dev_root) / name).string()});
    }
  }
  std::vector<UsbCamera> out;
  for (auto& [dir, cam] : cameras) {
    std::sort(cam.video.begin(), cam.video.end(), [](const UsbVideoNode& a, const UsbVideoNode& b) {
      return numberAfter(a.name, "video") < numberAfter(b.name, "video");
    });
    std::sort(cam.iio.begin(), cam.iio.end(), [](const UsbIioDevice& a, const UsbIioDevice& b) {
      return numberAfter(fs::path(a.sys_dir).filename().string(), "iio:device") <
             numberAfter(fs::path(b.sys_dir).filename().string(), "iio:device");
    });
    out.push_back(cam);
  }
  return out;
}

}  // namespace adugs::data

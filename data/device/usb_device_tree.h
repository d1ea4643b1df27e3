#pragma once
// Finding a USB camera's kernel devices through sysfs, by the USB vendor:product id, not by node
// number: its V4L2 nodes (/sys/class/video4linux/videoN) and its IIO devices
// (/sys/bus/iio/devices/iio:deviceN, e.g. the D435i's HID accel_3d and gyro_3d), each matched to
// the camera by walking from the device's sysfs directory up to the USB device that holds
// idVendor and idProduct. A machine with a laptop's own sensor hub (another accel_3d) or two
// cameras then never mixes them up.
//
// The roots are options so that tests run on a folder tree built like sysfs (symbolic links
// included) and /dev (FIFOs for the IIO device files).
#include <string>
#include <vector>

namespace adugs::data {

struct UsbVideoNode {
  std::string name;       // "video2"
  std::string dev_path;   // DEV_ROOT/video2
  std::string interface;  // the USB interface's sysfs directory (video and metadata nodes share it)
  int index = -1;         // sysfs `index` (0: the interface's video node, 1: its metadata node)
};

struct UsbIioDevice {
  std::string name;      // sysfs `name`: "accel_3d", "gyro_3d"
  std::string sys_dir;   // SYS_ROOT/bus/iio/devices/iio:device3
  std::string dev_path;  // DEV_ROOT/iio:device3
};

struct UsbCamera {
  std::string usb_dir;  // the USB device's sysfs directory (resolved)
  std::string bus_port; // its name, e.g. "2-1"
  std::string vendor_id, product_id;  // lower-case hex, "8086", "0b3a"
  std::string serial, product, speed;  // sysfs serial, product, speed (Mb/s); "" when absent
  std::vector<UsbVideoNode> video;     // by node number
  std::vector<UsbIioDevice> iio;       // by device number
};

// Every USB device with a V4L2 node whose id matches `id` ("8086:0b3a"; "8086" for any product of
// the vendor; "" for all), sorted by sysfs path.
std::vector<UsbCamera> findUsbCameras(const std::string& sys_root, const std::string& dev_root, const std::string& id);

}  // namespace adugs::data

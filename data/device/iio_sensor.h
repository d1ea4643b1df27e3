#pragma once
// One Linux IIO device read in buffered mode (the D435i's HID accel_3d / gyro_3d): its scan
// elements from sysfs, the three axes of one channel type and the timestamp enabled (everything
// else off), the sampling frequency set, the kernel buffer enabled, and records read from
// /dev/iio:deviceN without blocking (poll fd() first). Closing disables the buffer again.
//
// sysfs, under the device's directory:
//   scan_elements/in_<X>_en, _index, _type   per element (X = accel_x ... anglvel_z, timestamp)
//   in_<type>_sampling_frequency             Hz (the HID driver turns it into a report interval)
//   buffer/length, buffer/enable             kernel FIFO length in records, streaming on/off
//   trigger/current_trigger                  the HID driver's own trigger, "<name>-dev<N>"
//   current_timestamp_clock                  which clock stamps records when the device sends no
//                                            timestamp of its own (realtime by default; set to
//                                            realtime on open, which device stamps never come near)
// Setting up is an InputError naming the sysfs file when it cannot be read or written (usually
// permissions: the udev rule of the README). While streaming, a read error or end of file (the
// device went away) ends the sensor (gone()) with a message instead of throwing.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "data/device/iio_scan.h"
#include "data/device/usb_device_tree.h"

namespace adugs::data {

// What sysfs says about an IIO device, for `adugs d435i info` and for opening it.
struct IioDeviceInfo {
  std::string name;
  std::vector<data::IioChannel> channels;  // every scan element, with its index and type
  std::vector<bool> enabled;               // per channel
  std::string sampling_frequency_file;     // "" when the device has none
  std::string sampling_frequency;          // its text
  std::string sampling_frequency_available;
  std::string scale;                       // in_<type>_scale (the kernel's idea of the unit)
  std::string hysteresis;                  // in_<type>_hysteresis: on D4xx firmware 5.16+ the IMU
                                           // range (librealsense's gyro/accel sensitivity); left alone
  std::string timestamp_clock;             // current_timestamp_clock
};
// `type` is the channel type whose rate and scale files are read ("accel", "anglvel").
IioDeviceInfo readIioDeviceInfo(const UsbIioDevice& device, const std::string& type);

struct IioSample {
  int64_t timestamp_ns = 0;        // the record's timestamp element
  Eigen::Vector3d counts{0, 0, 0}; // raw x, y, z as the device sent them
};

class IioSensor {
 public:
  // `type`: "accel" or "anglvel". rate_hz > 0 is written to the sampling frequency file.
  IioSensor(const UsbIioDevice& device, const std::string& type, double rate_hz, int buffer_records);
  ~IioSensor();
  IioSensor(const IioSensor&) = delete;
  IioSensor& operator=(const IioSensor&) = delete;

  int fd() const { return fd_; }
  const std::string& devPath() const { return device_.dev_path; }
  // The rate the device reports after setting it (0 if it has no rate file).
  double rateHz() const { return rate_hz_; }
  // Meaningful bits of the x axis (16 or 32 on a D4xx: the firmware's data width).
  int axisRealBits() const { return channels_[axis_[0]].type.real_bits; }
  size_t recordBytes() const { return record_bytes_; }
  // The clock the kernel stamps records with when the device sends no timestamp of its own
  // (current_timestamp_clock: "realtime", set on open when permitted; "monotonic", "boottime"...).
  const std::string& hostStampClock() const { return host_stamp_clock_; }

  // Appends every complete record available now. False once the device is gone.
  bool read(std::vector<IioSample>* out);
  bool gone() const { return gone_; }
  const std::string& message() const { return message_; }

 private:
  void writeAttribute(const std::string& relative, const std::string& value, bool required);

  UsbIioDevice device_;
  std::string type_;
  std::vector<data::IioChannel> channels_;  // enabled ones, laid out
  size_t axis_[3] = {0, 0, 0};
  size_t timestamp_ = 0;
  size_t record_bytes_ = 0;
  double rate_hz_ = 0;
  std::string host_stamp_clock_ = "realtime";
  int fd_ = -1;
  bool buffer_enabled_ = false;
  std::vector<uint8_t> pending_;  // bytes of a record cut by a read
  bool gone_ = false;
  std::string message_;
};

}  // namespace adugs::data

#pragma once
// The RealSense D4xx depth module's controls on its depth/infrared node: the emitter (projector)
// and the infrared exposure through the camera's UVC extension unit (UVCIOC_CTRL_QUERY), the gain
// through the standard UVC processing unit (V4L2_CID_GAIN). Identifiers from librealsense's
// src/ds/ds-private.h (depth_xu: unit 3, GUID C9606CCB-594C-4D25-AF47-CCC496435995) and
// d400-device.cpp / ds-options.cpp (sizes and units):
//   selector 2  DS5_DEPTH_EMITTER_ENABLED  u8   0 off, 1 laser, 2 laser auto, 3 LED
//   selector 3  DS5_EXPOSURE               u32  microseconds (manual exposure)
//   selector 11 DS5_ENABLE_AUTO_EXPOSURE   u8   0 manual, 1 auto
#include <cstdint>
#include <string>

#include "data/device/v4l2_io.h"

namespace adugs::data {

constexpr uint8_t kD4xxDepthXuUnit = 3;
constexpr uint8_t kD4xxEmitterSelector = 2;
constexpr uint8_t kD4xxExposureSelector = 3;
constexpr uint8_t kD4xxAutoExposureSelector = 0x0B;

class D4xxControls {
 public:
  // `fd` is the open depth/infrared node, `node` its path for messages.
  D4xxControls(V4l2Io& io, int fd, std::string node) : io_(io), fd_(fd), node_(std::move(node)) {}

  // Each returns false and sets error() when the camera refuses (EIO/EBUSY: not now; ENOENT or
  // EINVAL: no such control, e.g. another camera or uvcvideo without the unit mapped).
  bool readEmitter(uint8_t* mode);
  bool setEmitter(uint8_t mode);
  bool readAutoExposure(bool* on);
  bool setAutoExposure(bool on);
  bool readExposureUs(uint32_t* us);
  bool setExposureUs(uint32_t us);
  bool readGain(int* gain);
  bool setGain(int gain);
  const std::string& error() const { return error_; }

 private:
  bool query(uint8_t selector, uint8_t request, uint8_t* data, uint16_t size, const char* name);

  V4l2Io& io_;
  int fd_;
  std::string node_;
  std::string error_;
};

// A UVC camera's standard exposure controls (the D4xx colour node): exposure_us > 0 sets manual
// exposure (V4L2_CID_EXPOSURE_AUTO = manual, V4L2_CID_EXPOSURE_ABSOLUTE in units of 100 us) and
// gain > 0 the gain; exposure_us == 0 selects auto exposure (aperture priority). False with
// *error set when the camera refuses.
bool setUvcExposure(V4l2Io& io, int fd, int exposure_us, int gain, std::string* error);

}  // namespace adugs::data

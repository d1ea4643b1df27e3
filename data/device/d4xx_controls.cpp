#include "data/device/d4xx_controls.h"

#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <linux/videodev2.h>

#include <algorithm>

namespace adugs::data {

bool D4xxControls::query(uint8_t selector, uint8_t request, uint8_t* data, uint16_t size, const char* name) {
  uvc_xu_control_query q{};
  q.unit = kD4xxDepthXuUnit;
  q.selector = selector;
  q.query = request;
  q.size = size;
  q.data = data;
  const int r = io_.ioctl(fd_, UVCIOC_CTRL_QUERY, &q);
  if (r < 0) {
    error_ = node_ + ": " + (request == UVC_SET_CUR ? "setting " : "reading ") + name +
             " (UVC extension unit 3, selector " + std::to_string(selector) + "): " + errnoText(r);
    return false;
  }
  return true;
}

bool D4xxControls::readEmitter(uint8_t* mode) { return query(kD4xxEmitterSelector, UVC_GET_CUR, mode, 1, "the emitter"); }

bool D4xxControls::setEmitter(uint8_t mode) { return query(kD4xxEmitterSelector, UVC_SET_CUR, &mode, 1, "the emitter"); }

bool D4xxControls::readAutoExposure(bool* on) {
  uint8_t v = 0;
  if (!query(kD4xxAutoExposureSelector, UVC_GET_CUR, &v, 1, "auto exposure")) return false;
  *on = v != 0;
  return true;
}

bool D4xxControls::setAutoExposure(bool on) {
  uint8_t v = on ? 1 : 0;
  return query(kD4xxAutoExposureSelector, UVC_SET_CUR, &v, 1, "auto exposure");
}

bool D4xxControls::readExposureUs(uint32_t* us) {
  uint8_t b[4] = {0, 0, 0, 0};
  if (!query(kD4xxExposureSelector, UVC_GET_CUR, b, 4, "the exposure")) return false;
  *us = static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) | (static_cast<uint32_t>(b[2]) << 16) |
        (static_cast<uint32_t>(b[3]) << 24);  // UVC controls are little-endian
  return true;
}

bool D4xxControls::setExposureUs(uint32_t us) {
  uint8_t b[4] = {static_cast<uint8_t>(us), static_cast<uint8_t>(us >> 8), static_cast<uint8_t>(us >> 16),
                  static_cast<uint8_t>(us >> 24)};
  return query(kD4xxExposureSelector, UVC_SET_CUR, b, 4, "the exposure");
}

bool D4xxControls::readGain(int* gain) {
  v4l2_control c{};
  c.id = V4L2_CID_GAIN;
  const int r = io_.ioctl(fd_, VIDIOC_G_CTRL, &c);
  if (r < 0) {
    error_ = node_ + ": reading the gain (V4L2_CID_GAIN): " + errnoText(r);
    return false;
  }
  *gain = c.value;
  return true;
}

bool D4xxControls::setGain(int gain) {
  v4l2_control c{};
  c.id = V4L2_CID_GAIN;
  c.value = gain;
  const int r = io_.ioctl(fd_, VIDIOC_S_CTRL, &c);
  if (r < 0) {
    error_ = node_ + ": setting the gain (V4L2_CID_GAIN) to " + std::to_string(gain) + ": " + errnoText(r);
    return false;
  }
  return true;
}

bool setUvcExposure(V4l2Io& io, int fd, int exposure_us, int gain, std::string* error) {
  const auto set = [&](uint32_t id, int value, const char* name) {
    v4l2_control c{};
    c.id = id;
    c.value = value;
    const int r = io.ioctl(fd, VIDIOC_S_CTRL, &c);
    if (r < 0) *error = std::string("setting ") + name + " to " + std::to_string(value) + ": " + errnoText(r);
    return r >= 0;
  };
  if (exposure_us == 0) return set(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_APERTURE_PRIORITY, "auto exposure");
  return set(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "manual exposure") &&
         set(V4L2_CID_EXPOSURE_ABSOLUTE, std::max(1, (exposure_us + 50) / 100), "the exposure (100 us units)") &&
         (gain <= 0 || set(V4L2_CID_GAIN, gain, "the gain"));
}

}  // namespace adugs::data

#pragma once
// `adugs live --v4l2 /dev/videoN`: any V4L2 camera (webcam, the D435i's colour node as a plain
// camera), vision only, through OpenCV's V4L2 backend (cv::VideoCapture with cv::CAP_V4L2, in
// libadugs_media.so: data/media/media_module.h).
// OpenCV rather than ViSP's vpV4l2Grabber: most USB cameras give 640x480 and more at 30 Hz only
// as MJPEG, which vpV4l2Grabber cannot decode (GREY, RGB24/32, BGR24, YUYV only), and
// vpV4l2Grabber cannot set the frame rate; OpenCV's backend does both, and reports the driver's
// buffer timestamp (CLOCK_MONOTONIC for UVC cameras) as CAP_PROP_POS_MSEC, which becomes the
// frame's stamp.
//
// next() blocks until the next frame (the driver's buffers are drained at the camera's rate). A
// camera that stops delivering (unplugged) ends the source: next() returns false, stopReason()
// says why. stop() takes effect at the next frame (the driver wait is not interruptible).
#include <atomic>
#include <memory>
#include <string>

#include "data/media/media_module.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

struct V4l2Request {
  int width = 0, height = 0;  // 0: the camera's current
  double fps = 0;             // 0: the camera's current
  std::string fourcc;         // e.g. "MJPG", "YUYV", "GREY"; "" = the camera's current
};

class V4l2CameraSource : public data::SequenceSource {
 public:
  // InputError naming the device when it cannot be opened or gives no first frame.
  V4l2CameraSource(const std::string& device, const V4l2Request& request);

  bool next(data::Measurement& m) override;
  data::SourceCounts counts() const override { return {}; }
  std::string description() const override;
  std::string stopReason() const override { return ended_; }
  bool isLive() const override { return true; }
  void stop() override { stopped_ = true; }

  int width() const { return width_; }
  int height() const { return height_; }
  double frameRateHz() const { return fps_; }

 private:
  bool grab(data::Frame* frame);

  std::string device_;
  std::unique_ptr<VideoInput> capture_;
  int width_ = 0, height_ = 0;
  double fps_ = 0;
  std::string fourcc_;
  data::Frame first_;
  bool has_first_ = false;
  int64_t last_t_ = -1;
  size_t delivered_ = 0;
  std::string ended_;  // why the camera stopped (written by next()'s thread, read after it ended)
  std::atomic<bool> stopped_{false};
};

}  // namespace adugs::data

#include "data/sources/v4l2_camera_source.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>  // the cv::CAP_PROP_* constants only

#include "data/input_error.h"
#include "data/media/media_loader.h"

namespace adugs::data {

V4l2CameraSource::V4l2CameraSource(const std::string& device, const V4l2Request& request) : device_(device) {
  std::error_code ec;
  if (!std::filesystem::exists(device, ec))
    throw data::InputError(device, 0, "--v4l2", "no such device (list cameras with: v4l2-ctl --list-devices)");
  capture_.reset(requireMediaModule(device, "--v4l2", "V4L2 cameras").open_v4l2_camera(device));
  if (!capture_)
    throw data::InputError(device, 0, "--v4l2",
                           "cannot open as a V4L2 camera (is it a capture node? are you in the 'video' group?)");
  if (!request.fourcc.empty()) {
    if (request.fourcc.size() != 4) throw data::InputError(device, 0, "--v4l2-format", "must be 4 characters, e.g. MJPG");
    const std::string& f = request.fourcc;
    if (!capture_->set(cv::CAP_PROP_FOURCC, fourccCode(f[0], f[1], f[2], f[3])))
      throw data::InputError(device, 0, "--v4l2-format", "the camera refuses the pixel format " + f);
  }
  if (request.width > 0) capture_->set(cv::CAP_PROP_FRAME_WIDTH, request.width);
  if (request.height > 0) capture_->set(cv::CAP_PROP_FRAME_HEIGHT, request.height);
  if (request.fps > 0) capture_->set(cv::CAP_PROP_FPS, request.fps);
  if (!grab(&first_)) throw data::InputError(device, 0, "--v4l2", "the camera gave no frame");
  has_first_ = true;
  width_ = first_.image.cols;
  height_ = first_.image.rows;
  fps_ = capture_->get(cv::CAP_PROP_FPS);
  const int code = static_cast<int>(capture_->get(cv::CAP_PROP_FOURCC));
  for (int i = 0; i < 4; ++i) fourcc_ += static_cast<char>((code >> (8 * i)) & 0xff);
  if ((request.width > 0 && request.width != width_) || (request.height > 0 && request.height != height_))
    std::fprintf(stderr, "adugs: warning: %s: asked for %dx%d, the camera gives %dx%d\n", device.c_str(), request.width,
                 request.height, width_, height_);
}

bool V4l2CameraSource::grab(data::Frame* frame) {
  cv::Mat image;
  if (!capture_->read(image) || image.empty()) return false;
  // The driver's buffer time; a driver without one (0) gets the host's monotonic clock.
  int64_t t = static_cast<int64_t>(capture_->get(cv::CAP_PROP_POS_MSEC) * 1e6);
  if (t <= 0)
    t = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (last_t_ >= 0 && t <= last_t_) t = last_t_ + 1;
  last_t_ = t;
  frame->t_ns = t;
  frame->path = device_;
  if (image.channels() == 3) {
    frame->colour = image;
    cv::cvtColor(image, frame->image, cv::COLOR_BGR2GRAY);
  } else {
    frame->image = image;
    frame->colour = cv::Mat();
  }
  return true;
}

bool V4l2CameraSource::next(data::Measurement& m) {
  if (stopped_ || !ended_.empty()) return false;
  m.type = data::Measurement::Type::kFrame;
  if (has_first_) {
    m.frame = std::move(first_);
    has_first_ = false;
  } else if (!grab(&m.frame)) {
    ended_ = "the camera stopped delivering frames after " + std::to_string(delivered_) + " (unplugged?)";
    return false;
  }
  ++delivered_;
  return true;
}

std::string V4l2CameraSource::description() const {
  char text[160];
  std::snprintf(text, sizeof text, "V4L2 camera %s (%dx%d %s at %.3g Hz, OpenCV V4L2 backend)", device_.c_str(), width_,
                height_, fourcc_.c_str(), fps_);
  return text;
}

}  // namespace adugs::data

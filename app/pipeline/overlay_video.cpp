#include "app/pipeline/overlay_video.h"

#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "data/input_error.h"
#include "data/media/media_loader.h"

namespace adugs::app {

cv::Mat drawOverlay(const cv::Mat& image, const OverlayContent& c) {
  cv::Mat out;
  if (image.channels() == 1)
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  else
    out = image.clone();
  if (!c.mask.empty()) {
    cv::Mat red(out.size(), CV_8UC3, cv::Scalar(0, 0, 255)), tinted;
    cv::addWeighted(out, 0.6, red, 0.4, 0, tinted);
    tinted.copyTo(out, c.mask);
  }
  for (const tracking::TrackedObject& t : c.objects) {
    const cv::Scalar colour((t.id * 67) % 256, (t.id * 151) % 256, (t.id * 37 + 128) % 256);
    cv::rectangle(out, t.box.rect(), colour, t.detected ? 2 : 1);
    if (t.id > 0)
      cv::putText(out, std::to_string(t.id), {static_cast<int>(t.box.left()), static_cast<int>(t.box.top()) - 3},
                  cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1);
  }
  for (const cv::Point2f& p : c.kept) cv::circle(out, p, 2, cv::Scalar(0, 220, 0), cv::FILLED);
  for (const cv::Point2f& p : c.dropped) cv::drawMarker(out, p, cv::Scalar(0, 0, 255), cv::MARKER_CROSS, 7, 2);
  if (!c.status.empty()) {
    cv::rectangle(out, {0, out.rows - 22}, {out.cols, out.rows}, cv::Scalar(0, 0, 0), cv::FILLED);
    cv::putText(out, c.status, {6, out.rows - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1);
  }
  return out;
}

OverlayVideo::OverlayVideo(const std::string& path, double fps) : path_(path), fps_(fps > 0 ? fps : 20) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".avi")
    fourcc_ = data::fourccCode('M', 'J', 'P', 'G');
  else if (ext == ".mp4")
    fourcc_ = data::fourccCode('m', 'p', '4', 'v');
  else
    throw data::InputError(path, 0, "--overlay", "the overlay video must end in .avi or .mp4");
}

void OverlayVideo::write(const cv::Mat& bgr) {
  if (!writer_) {
    const auto parent = std::filesystem::path(path_).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    writer_.reset(data::requireMediaModule(path_, "--overlay", "overlay videos").open_video_writer(path_, fourcc_, fps_, bgr.size()));
    if (!writer_) throw data::InputError(path_, 0, "--overlay", "OpenCV cannot write this video");
  }
  writer_->write(bgr);
  ++frames_;
}

}  // namespace adugs::app

#pragma once
// The dynamic stage drawn over the frames (the paper's Fig. 1/3 view) and written as a video:
// dynamic mask tinted red, tracked boxes with their ids (thick: detected in this frame, thin:
// predicted), features kept (green dots) and dropped as dynamic (red crosses), a status line.
// Used by `adugs run --overlay` and `adugs track --overlay`.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/media/media_module.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::app {

struct OverlayContent {
  cv::Mat mask;                                  // CV_8UC1, 255 = dynamic; empty = none
  std::vector<tracking::TrackedObject> objects;  // boxes with ids
  std::vector<cv::Point2f> kept, dropped;        // features
  std::string status;                            // bottom line
};

// Draws onto a BGR copy of `image` (grey or BGR).
cv::Mat drawOverlay(const cv::Mat& image, const OverlayContent& content);

// Writes the frames to .avi (MJPG) or .mp4 (mp4v); opens on the first frame (its size). Throws
// data::InputError naming the file when it cannot be written or the extension is another.
// OpenCV's video writer is in libadugs_media.so (data/media/media_module.h).
class OverlayVideo {
 public:
  OverlayVideo(const std::string& path, double fps);
  void write(const cv::Mat& bgr);
  int frames() const { return frames_; }

 private:
  std::string path_;
  double fps_;
  int fourcc_;
  std::unique_ptr<data::VideoOutput> writer_;
  int frames_ = 0;
};

}  // namespace adugs::app

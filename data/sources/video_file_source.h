#pragma once
// `adugs live --video FILE`: a video file (any format OpenCV reads; or an image folder) played as
// a live camera: each frame delivered when its stream time comes (wall clock since the first
// frame, divided by `speed`), grey for the tracker and in colour for detectors and the view.
// No IMU: vision only. Frames are read by data::ImageSource.
#include <chrono>
#include <memory>
#include <string>

#include "data/sources/image_source.h"
#include "data/sources/paced_clock.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

class VideoFileSource : public data::SequenceSource {
 public:
  // Reads the first frame (size, so the caller can guess a camera); InputError if unreadable.
  explicit VideoFileSource(const std::string& path, double speed = 1.0);

  bool next(data::Measurement& m) override;
  data::SourceCounts counts() const override { return {}; }
  std::string description() const override;
  bool isLive() const override { return true; }
  void stop() override { clock_.stop(); }

  int width() const { return width_; }
  int height() const { return height_; }
  double frameRateHz() const { return rate_hz_; }  // from the first two stamps (0 if unknown)

 private:
  bool read(data::ImageFrame& frame);

  std::string path_;
  double speed_;
  data::ImageSource images_;
  data::ImageFrame first_, second_;
  int pending_ = 0;  // frames already read ahead (first_, second_)
  int width_ = 0, height_ = 0;
  double rate_hz_ = 0;
  int64_t first_t_ = -1, last_t_ = -1;
  size_t delivered_ = 0;
  std::chrono::steady_clock::time_point wall_start_;
  PacedClock clock_;
};

}  // namespace adugs::data

#include "data/sources/video_file_source.h"

#include <cstdio>

#include "data/input_error.h"

namespace adugs::data {

VideoFileSource::VideoFileSource(const std::string& path, double speed)
    : path_(path), speed_(speed), images_(path) {
  if (!(speed_ > 0)) throw data::InputError("--speed", 0, "speed", "must be positive");
  if (!images_.next(first_)) throw data::InputError(path, 0, "", "no frame could be read from this video");
  pending_ = 1;
  width_ = first_.gray.cols;
  height_ = first_.gray.rows;
  if (images_.next(second_)) {
    pending_ = 2;
    if (second_.t_ns > first_.t_ns) rate_hz_ = 1e9 / static_cast<double>(second_.t_ns - first_.t_ns);
  }
}

bool VideoFileSource::read(data::ImageFrame& frame) {
  if (pending_ > 0) {
    frame = std::move(first_);
    if (pending_ == 2) first_ = std::move(second_);
    --pending_;
    return true;
  }
  return images_.next(frame);
}

bool VideoFileSource::next(data::Measurement& m) {
  data::ImageFrame f;
  if (clock_.stopped() || !read(f)) return false;
  // Stamps must increase; a container that repeats or loses its clock gets the nominal step.
  int64_t t = f.t_ns;
  if (last_t_ >= 0 && t <= last_t_) t = last_t_ + (rate_hz_ > 0 ? static_cast<int64_t>(1e9 / rate_hz_) : 1'000'000);
  if (first_t_ < 0) {
    first_t_ = t;
    wall_start_ = std::chrono::steady_clock::now();
  }
  last_t_ = t;
  const auto due = wall_start_ + std::chrono::nanoseconds(static_cast<int64_t>(static_cast<double>(t - first_t_) / speed_));
  if (!clock_.waitUntil(due)) return false;
  m.type = data::Measurement::Type::kFrame;
  m.frame.t_ns = t;
  m.frame.path = f.name;
  m.frame.image = f.gray;
  m.frame.colour = f.image.channels() == 3 ? f.image : cv::Mat();
  ++delivered_;
  return true;
}

std::string VideoFileSource::description() const {
  char rate[64];
  std::snprintf(rate, sizeof rate, "%.3g Hz", rate_hz_);
  return "video " + path_ + " played as a live camera (" + std::to_string(width()) + "x" + std::to_string(height()) +
         ", " + rate + (speed_ != 1.0 ? ", at " + std::to_string(speed_) + "x" : std::string()) + ")";
}

}  // namespace adugs::data

#pragma once
// What the estimator knows after each frame, fed back to the stages ahead of it: the gyro bias
// (the front-end's KLT rotation prediction, the masker's camera-motion compensation) and, once
// initialised, its whole state (the motion cue carries it with the IMU to the frame it works on). A
// stage working on frame k asks for frame k - d, for a fixed d, and waits until the estimator has
// it: what it gets never depends on the threads' timing, so a playback is reproducible to the byte.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "vio/imu/imu_integrator.h"  // NavState

namespace adugs::app {

class EstimatorFeedback {
 public:
  struct AfterFrame {
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
    // The state after the frame, once initialised; its t_ns is on the IMU clock (the frame's
    // camera stamp frame_t_ns plus the camera-IMU time offset).
    std::optional<vio::NavState> state;
    int64_t frame_t_ns = 0;
  };

  // What holds after the estimator's next frame (frames are numbered 0, 1, ... in the order given).
  void publish(const Eigen::Vector3d& gyro_bias, const std::optional<vio::NavState>& state = std::nullopt,
               int64_t frame_t_ns = 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    frames_.push_back({gyro_bias, state, frame_t_ns});
    ++published_count_;
    if (frames_.size() > kKept) frames_.pop_front();
    published_.notify_all();
  }

  // What held after frame `index` (zero bias and no velocity for index < 0, before any estimate
  // exists). False when closed before that frame came.
  bool waitFor(int index, AfterFrame* after) {
    if (index < 0) {
      *after = AfterFrame();
      return true;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    published_.wait(lock, [&] { return closed_ || published_count_ > index; });
    if (published_count_ <= index) return false;
    const int64_t first_kept = published_count_ - static_cast<int64_t>(frames_.size());
    if (index < first_kept)
      throw std::logic_error("EstimatorFeedback: frame " + std::to_string(index) + " asked for after it was dropped");
    *after = frames_[static_cast<size_t>(index - first_kept)];
    return true;
  }
  // The bias alone.
  bool waitFor(int index, Eigen::Vector3d* gyro_bias) {
    AfterFrame after;
    if (!waitFor(index, &after)) return false;
    *gyro_bias = after.gyro_bias;
    return true;
  }

  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    published_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable published_;
  // The newest frames only: the stages ask for a few frames back, and the channels between them
  // hold a handful of frames, so the memory stays flat however long the run.
  static constexpr size_t kKept = 1024;
  std::deque<AfterFrame> frames_;
  int64_t published_count_ = 0;
  bool closed_ = false;
};

}  // namespace adugs::app

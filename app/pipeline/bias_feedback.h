#pragma once
// The estimator's gyro bias after each frame, fed back to the stages ahead of it (the front-end's
// KLT rotation prediction, the masker's camera-motion compensation). A stage working on frame k
// asks for the bias after frame k - d, for a fixed d, and waits until the estimator has it: what
// it gets never depends on the threads' timing, so a playback is reproducible to the byte.
#include <condition_variable>
#include <mutex>
#include <vector>

#include <Eigen/Core>

namespace adugs::app {

class BiasFeedback {
 public:
  // The bias after the estimator's next frame (frames are numbered 0, 1, ... in the order given).
  void publish(const Eigen::Vector3d& gyro_bias) {
    std::lock_guard<std::mutex> lock(mutex_);
    biases_.push_back(gyro_bias);
    published_.notify_all();
  }

  // The bias after frame `index` (zero for index < 0, before any estimate exists). False when
  // closed before that frame's bias came.
  bool waitFor(int index, Eigen::Vector3d* gyro_bias) {
    if (index < 0) {
      gyro_bias->setZero();
      return true;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    published_.wait(lock, [&] { return closed_ || static_cast<int>(biases_.size()) > index; });
    if (static_cast<int>(biases_.size()) <= index) return false;
    *gyro_bias = biases_[index];
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
  std::vector<Eigen::Vector3d> biases_;  // 24 bytes a frame: an hour at 30 Hz is 2.6 MB
  bool closed_ = false;
};

}  // namespace adugs::app

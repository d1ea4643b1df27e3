#include "app/pipeline/frame_gate.h"

#include <stdexcept>

namespace adugs::app {

FrameGate::FrameGate(size_t capacity, Policy policy) : capacity_(capacity), policy_(policy) {
  if (capacity_ == 0) throw std::invalid_argument("FrameGate: capacity must be at least 1");
}

void FrameGate::addImu(const data::ImuSample& sample) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_imu_.push_back(sample);
}

bool FrameGate::addFrame(data::Frame frame, double sequence_s, std::chrono::steady_clock::time_point acquired_at) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (policy_ == Policy::kWait) not_full_.wait(lock, [&] { return closed_ || waiting_.size() < capacity_; });
  if (closed_) return false;
  if (waiting_.size() >= capacity_) {
    // kDropOldest: the oldest waiting frame goes; its IMU samples are put in front of the next
    // one's (or of the new frame's), so the IMU stream stays whole.
    PipelineFrame oldest = std::move(waiting_.front());
    waiting_.pop_front();
    std::vector<data::ImuSample>& next_imu = waiting_.empty() ? pending_imu_ : waiting_.front().imu;
    oldest.imu.insert(oldest.imu.end(), next_imu.begin(), next_imu.end());
    next_imu = std::move(oldest.imu);
    ++dropped_;
  }
  PipelineFrame f;
  f.frame = std::move(frame);
  f.imu = std::move(pending_imu_);
  pending_imu_.clear();
  f.sequence_s = sequence_s;
  f.acquired_at = acquired_at;
  waiting_.push_back(std::move(f));
  not_empty_.notify_one();
  return true;
}

bool FrameGate::pop(PipelineFrame* out) {
  std::unique_lock<std::mutex> lock(mutex_);
  not_empty_.wait(lock, [&] { return closed_ || !waiting_.empty(); });
  if (waiting_.empty()) return false;
  *out = std::move(waiting_.front());
  waiting_.pop_front();
  out->index = next_index_++;
  not_full_.notify_one();
  return true;
}

void FrameGate::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  not_empty_.notify_all();
  not_full_.notify_all();
}

size_t FrameGate::framesDropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

size_t FrameGate::imuPending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_imu_.size();
}

}  // namespace adugs::app

#pragma once
// Waiting for a live source's next delivery time, interruptible by stop() from another thread.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

namespace adugs::data {

class PacedClock {
 public:
  // False when stopped (now or during the wait).
  bool waitUntil(std::chrono::steady_clock::time_point due) {
    std::unique_lock<std::mutex> lock(mutex_);
    return !cv_.wait_until(lock, due, [&] { return stopped_.load(); });
  }
  void stop() {
    stopped_ = true;
    std::lock_guard<std::mutex> lock(mutex_);
    cv_.notify_all();
  }
  bool stopped() const { return stopped_; }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::atomic<bool> stopped_{false};
};

}  // namespace adugs::data

#pragma once
// Puts messages back into header-stamp order. Recorders write a message when it arrives, not
// when it was stamped (a camera image is recorded tens of ms after its exposure stamp, IMU
// samples within a few ms), so a bag read in record order is out of stamp order. The buffer holds
// messages until one stamped more than `window_ns` later has been seen, then releases the oldest.
// A message stamped before one already released is too late to be put in order: it is refused
// (push returns false) and counted by the caller. Memory: the messages of one window.
//
// Ties on the stamp are released by `rank` (smaller first: IMU before images), then arrival.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace adugs::data {

template <typename T>
class StampReorderBuffer {
 public:
  explicit StampReorderBuffer(int64_t window_ns) : window_ns_(window_ns) {}

  // False (and the message is dropped) when it is older than the last released one.
  bool push(int64_t stamp_ns, int rank, T value) {
    if (released_any_ && stamp_ns < last_released_ns_) return false;
    newest_ns_ = std::max(newest_ns_, stamp_ns);
    heap_.push(Entry{stamp_ns, rank, arrivals_++, std::move(value)});
    return true;
  }

  // Releases the oldest message if the window has passed it (or `flush`, at the end of input).
  bool pop(T* out, int64_t* stamp_ns, bool flush = false) {
    if (heap_.empty()) return false;
    const Entry& top = heap_.top();
    if (!flush && newest_ns_ - top.stamp_ns <= window_ns_) return false;
    last_released_ns_ = top.stamp_ns;
    released_any_ = true;
    *stamp_ns = top.stamp_ns;
    *out = std::move(const_cast<Entry&>(top).value);  // moved out right before pop()
    heap_.pop();
    return true;
  }

  size_t size() const { return heap_.size(); }

 private:
  struct Entry {
    int64_t stamp_ns;
    int rank;
    uint64_t arrival;
    T value;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const {
      if (a.stamp_ns != b.stamp_ns) return a.stamp_ns > b.stamp_ns;
      if (a.rank != b.rank) return a.rank > b.rank;
      return a.arrival > b.arrival;
    }
  };
  int64_t window_ns_;
  int64_t newest_ns_ = std::numeric_limits<int64_t>::min();
  int64_t last_released_ns_ = 0;
  bool released_any_ = false;
  uint64_t arrivals_ = 0;
  std::priority_queue<Entry, std::vector<Entry>, Later> heap_;
};

}  // namespace adugs::data

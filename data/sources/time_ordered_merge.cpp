#include "data/sources/time_ordered_merge.h"

#include <algorithm>

namespace adugs::data {

int TimeOrderedMerge::addStream(double latency_s) {
  Stream s;
  s.latency_ns = data::secToNs(latency_s);
  streams_.push_back(s);
  return static_cast<int>(streams_.size()) - 1;
}

bool TimeOrderedMerge::push(int stream, data::Measurement m) {
  Stream& s = streams_.at(static_cast<size_t>(stream));
  const int64_t t = m.timeNs();
  if (t <= s.newest) {
    ++s.out_of_order;
    return false;
  }
  if (t < last_released_ || (t == last_released_ && m.isImu())) {
    ++s.late;
    return false;
  }
  s.newest = t;
  queue_.emplace(std::make_pair(t, m.isImu() ? 0 : 1), std::move(m));
  return true;
}

bool TimeOrderedMerge::pop(int64_t now_ns, data::Measurement* m, bool flush) {
  if (queue_.empty()) return false;
  const int64_t t = queue_.begin()->first.first;
  if (!flush) {
    for (const Stream& s : streams_)
      if (t > std::max(s.newest, now_ns - s.latency_ns)) return false;  // s may still deliver before t
  }
  *m = std::move(queue_.begin()->second);
  queue_.erase(queue_.begin());
  last_released_ = t;
  return true;
}

int64_t TimeOrderedMerge::releaseDeadlineNs() const {
  if (queue_.empty()) return INT64_MAX;
  const int64_t t = queue_.begin()->first.first;
  int64_t deadline = INT64_MIN;
  for (const Stream& s : streams_)
    if (s.newest < t) deadline = std::max(deadline, t + s.latency_ns);
  return deadline;
}

}  // namespace adugs::data

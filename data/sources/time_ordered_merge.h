#pragma once
// The measurements of a device's live streams (frames, IMU samples), which reach the host each
// with its own delay, merged into one stream in time order (IMU first on equal stamps), as
// SequenceSource promises. A measurement is released once every stream has passed its stamp
// (each stream delivers in order) or has been silent past its latency bound: the most a
// measurement of that stream may arrive after its stamp. A measurement stamped before one already
// released, or not after the previous one of its stream, is refused and counted.
//
//   TimeOrderedMerge merge;
//   const int frames = merge.addStream(0.2), imu = merge.addStream(0.1);
//   merge.push(imu, sample);                  // as they arrive
//   if (merge.pop(nowNs(), &m)) ...           // the earliest, once nothing earlier can come
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "data/sources/sequence_source.h"

namespace adugs::data {

class TimeOrderedMerge {
 public:
  // A stream whose measurements arrive at most latency_s after their stamps. Returns its id.
  int addStream(double latency_s);
  // False (counted as late or out of order) when the measurement can no longer take its place.
  bool push(int stream, data::Measurement m);
  // The earliest measurement if nothing earlier can still come at host time now_ns (all of them,
  // in order, with flush: the streams have ended).
  bool pop(int64_t now_ns, data::Measurement* m, bool flush = false);
  // When the earliest pending measurement becomes releasable if no stream delivers (INT64_MAX:
  // nothing pending).
  int64_t releaseDeadlineNs() const;
  bool empty() const { return queue_.empty(); }
  size_t late(int stream) const { return streams_.at(static_cast<size_t>(stream)).late; }
  size_t outOfOrder(int stream) const { return streams_.at(static_cast<size_t>(stream)).out_of_order; }

 private:
  struct Stream {
    int64_t latency_ns = 0;
    int64_t newest = INT64_MIN;
    size_t late = 0, out_of_order = 0;
  };
  std::vector<Stream> streams_;
  std::multimap<std::pair<int64_t, int>, data::Measurement> queue_;  // (stamp, 0 IMU / 1 frame)
  int64_t last_released_ = INT64_MIN;
};

}  // namespace adugs::data

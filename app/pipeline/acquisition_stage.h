#pragma once
// The pipeline's first stage, on a thread of its own: reads the source (image decoding happens
// here) and hands IMU samples and frames to the entrance gate as they come. A live source is
// never kept waiting: the gate drops frames instead (app/pipeline/frame_gate.h).
#include <atomic>
#include <cstdint>
#include <mutex>

#include "app/pipeline/frame_gate.h"
#include "app/pipeline/pipeline_stats.h"
#include "data/sources/sequence_source.h"

namespace adugs::app {

class AcquisitionStage {
 public:
  explicit AcquisitionStage(data::SequenceSource& source) : source_(source) {}

  // Until the source ends, `stop` is set or the gate is closed; then closes the gate.
  // Exceptions (bad input, a device error) propagate.
  void run(FrameGate& gate, PipelineCounters& counters, const std::atomic<bool>& stop);

  // Thread-safe: what the source reported after its latest measurement.
  data::SourceCounts counts() const;
  int64_t firstTimeNs() const { return first_t_; }  // of the first measurement, -1 before

 private:
  data::SequenceSource& source_;
  std::atomic<int64_t> first_t_{-1};
  mutable std::mutex mutex_;
  data::SourceCounts counts_;
};

}  // namespace adugs::app

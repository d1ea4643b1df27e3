#include "app/pipeline/acquisition_stage.h"

#include <chrono>

namespace adugs::app {

void AcquisitionStage::run(FrameGate& gate, PipelineCounters& counters, const std::atomic<bool>& stop) {
  data::Measurement m;
  try {
    while (!stop && source_.next(m)) {
      if (first_t_ < 0) first_t_ = m.timeNs();
      if (m.isImu()) {
        gate.addImu(m.imu);
        ++counters.imu_acquired;
      } else {
        ++counters.frames_acquired;
        const double sequence_s = data::nsToSec(m.frame.t_ns - first_t_);
        if (!gate.addFrame(std::move(m.frame), sequence_s, std::chrono::steady_clock::now())) break;
        m.frame = data::Frame{};
      }
      std::lock_guard<std::mutex> lock(mutex_);
      counts_ = source_.counts();
    }
  } catch (...) {
    gate.close();
    throw;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  counts_ = source_.counts();
  gate.close();
}

data::SourceCounts AcquisitionStage::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

}  // namespace adugs::app

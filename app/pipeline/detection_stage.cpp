#include "app/pipeline/detection_stage.h"

#include <chrono>

#include "tracking/detect/detector_factory.h"
#include "tracking/dynamic_masker_options.h"

namespace adugs::app {

DetectionStage::DetectionStage(const std::string& detector_model, const std::string& detector_config,
                               int detect_every)
    : detect_every_(detect_every) {
  if (!detector_model.empty()) detector_ = tracking::makeDetector(detector_model, detector_config);
}

DetectionStage::~DetectionStage() = default;

void DetectionStage::run(FrameGate& in, Channel<PipelineFrame>& out) {
  PipelineFrame f;
  while (in.pop(&f)) {
    if (detector_ && tracking::isDetectionFrame(f.index, detect_every_)) {
      const auto t0 = std::chrono::steady_clock::now();
      f.detections = detector_->detect(f.frame.colour.empty() ? f.frame.image : f.frame.colour);
      f.detect_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    if (!out.push(std::move(f))) break;
  }
  out.close();
}

}  // namespace adugs::app

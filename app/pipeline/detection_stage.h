#pragma once
// The pipeline's detector stage, on a thread of its own ahead of the masking stage: the object
// detector (tracking/detect/detector_factory.h) on the frames tracking::isDetectionFrame() names
// (every detect_every-th frame from the first; the masking stage carries the boxes over the
// others), on the colour image when the source has one. Apart from the rest of the dynamic-mask chain (SORT,
// segmentation) so that on 2 cores the detector of frame k runs beside GrabCut of frame k-1.
// Without --mask detector it only passes frames on.
#include <memory>
#include <string>

#include "app/pipeline/channel.h"
#include "app/pipeline/frame_gate.h"

namespace adugs::tracking {
class Detector;
}  // namespace adugs::tracking

namespace adugs::app {

class DetectionStage {
 public:
  // detector_model "": no detector (frames pass through). Loading errors name the file.
  DetectionStage(const std::string& detector_model, const std::string& detector_config, int detect_every);
  ~DetectionStage();

  // Until `in` is drained or `out` closed; then closes `out`. Exceptions propagate.
  void run(FrameGate& in, Channel<PipelineFrame>& out);

 private:
  std::unique_ptr<tracking::Detector> detector_;
  int detect_every_;
};

}  // namespace adugs::app

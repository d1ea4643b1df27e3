#pragma once
// `adugs run --estimator vio`: EuRoC playback through the front-end (KLT + masked features) and
// the sliding-window visual-inertial estimator, one TUM pose per estimated frame (flushed).
#include <string>

namespace adugs::app {

struct VioRunArgs {
  std::string path, out_dir, gt_path, config_path;
  std::string mask = "none";  // none | gt (the simulator's mask0/ folder) | detector
  // --mask detector: YOLOX ONNX model, box segmenter (grabcut | box | mobilesam + its two ONNX).
  std::string detector_model, segmenter = "grabcut", sam_encoder, sam_decoder;
  bool skip_bad_frames = false;
  bool quiet = false;
};

void runVio(const VioRunArgs& args);

}  // namespace adugs::app

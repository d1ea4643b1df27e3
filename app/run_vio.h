#pragma once
// `adugs run --estimator vio`: playback (any SequenceSource) through the front-end (KLT + masked features) and
// the sliding-window visual-inertial estimator, one TUM pose per estimated frame (flushed).
#include <string>

#include "data/dataset_preset.h"

namespace adugs::app {

struct VioRunArgs {
  data::PlaybackOptions playback;  // what to play back (dataset preset, path, topics, calibration)
  std::string out_dir, config_path;
  std::string mask = "none";  // none | gt (the simulator's mask0/ folder) | detector
  // --mask detector: detector model, box segmenter (grabcut | box | mobilesam + its two files).
  std::string detector_model, segmenter = "grabcut", sam_encoder, sam_decoder;
  std::string detector_config;  // darknet .cfg ("" = beside the .weights)
  int detect_every = 0;  // > 0: overrides the run config's dynamic: detect_every
  std::string overlay;   // --overlay out.avi|.mp4
  bool quiet = false;
};

void runVio(const VioRunArgs& args);

}  // namespace adugs::app

#pragma once
// What `adugs run` and `adugs live` share: the pipeline (app/pipeline/pipeline.h) on an opened
// source, then OUT/trajectory.tum (flushed per pose), OUT/summary.yaml (always, also after Ctrl-C
// or an error: `end:` says which) and, when there is ground truth, the evaluation.
#include <string>

#include "data/dataset_preset.h"

namespace adugs::app {

// The dynamic-mask options of the command line (--mask ...).
struct MaskArgs {
  std::string mask = "none";  // none | gt (the simulator's mask0/ folder) | detector
  std::string detector_model, detector_config;  // darknet .cfg ("" = beside the .weights)
  std::string segmenter = "grabcut", sam_encoder, sam_decoder;
  int detect_every = 0;  // > 0: overrides the run config's dynamic: detect_every
};

struct PipelineRunArgs {
  std::string command = "run";  // run | live: the status line's prefix, the summary's `command:`
  std::string out_dir, config_path;
  MaskArgs mask;
  std::string overlay;  // --overlay out.avi|.mp4
  bool window = false;  // live view window
  bool quiet = false;
};

// Runs to the end of the source, Ctrl-C or an error (re-thrown after the outputs are written).
// sequence.has_imu false: vision only (masking and tracking; no trajectory).
void runPipeline(data::OpenedSequence& sequence, const PipelineRunArgs& args);

}  // namespace adugs::app

#pragma once
// What `adugs run` and `adugs live` share: the pipeline (app/pipeline/pipeline.h) on an opened
// source, then OUT/trajectory.tum (flushed per pose), OUT/summary.yaml (always, also after Ctrl-C
// or an error: `end:` says which) and, when there is ground truth, the evaluation.
#include <string>

#include "app/pipeline/masking_stage.h"
#include "data/sources/dataset_preset.h"

namespace adugs::app {

// The dynamic-mask options of the command line (--mask ...): the masking stage's options (its
// masker's options come from the run config's dynamic: map), and --detect-every, which overrides
// that map's detect_every.
struct MaskArgs {
  MaskingOptions masking;
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

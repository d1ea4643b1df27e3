#pragma once
// Command-line options shared by `adugs run`, `adugs live --replay` and `adugs record --replay`:
// how to open a recorded sequence (--dataset, topics, calibration, --start/--duration, ...) and the
// dynamic-mask options (--mask, --detector-model, ...).
#include <string>

#include <CLI/CLI.hpp>

#include "app/run_pipeline.h"
#include "data/sources/dataset_preset.h"

namespace adugs::app {

struct SequenceArgs {
  data::PlaybackOptions playback;  // the path is added by each command
  double start_s = 0, duration_s = 0, reorder_window_s = 0.1;
  CLI::Option* reorder_window = nullptr;  // given on the command line?
};

// Every sequence option except the path and --realtime.
void addSequenceOptions(CLI::App* cmd, SequenceArgs& args);
// The command line's playback options over the run config's `playback:` map over the preset.
data::PlaybackOptions playbackOptions(const SequenceArgs& args, const std::string& config_path);

void addMaskOptions(CLI::App* cmd, MaskArgs& args);

}  // namespace adugs::app

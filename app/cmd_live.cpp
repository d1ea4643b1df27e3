// `adugs live`: the odometry pipeline of `adugs run` (app/pipeline/pipeline.h) on a live source
// (app/live_sources.h): a sensor-paced replay of a recorded sequence, a video played as a
// camera, a V4L2 camera, or a RealSense D435i. Live sources cannot wait, so when the masking, front-end or estimator
// fall behind, frames are dropped (the oldest waiting one; counted in summary.yaml and on the
// status line), never IMU samples. Ctrl-C (SIGINT, SIGTERM) stops cleanly: the frames already
// inside are finished and every output written. The view: a window when $DISPLAY is set (quit with
// q), otherwise a status line per second; --overlay writes it as a video.
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/live_sources.h"
#include "app/pipeline/live_window.h"
#include "app/run_pipeline.h"

namespace adugs::app {
namespace {

struct LiveArgs {
  LiveSourceArgs source;
  std::string out_dir = "out/live";
  std::string config_path;
  MaskArgs mask;
  std::string overlay;
  bool no_window = false;
  bool quiet = false;
};

void runLive(const LiveArgs& a) {
  data::OpenedSequence sequence = openLiveSource(a.source, a.config_path, a.out_dir);
  PipelineRunArgs p;
  p.command = "live";
  p.out_dir = a.out_dir;
  p.config_path = a.config_path;
  p.mask = a.mask;
  p.overlay = a.overlay;
  std::string why;
  p.window = !a.no_window && LiveWindow::available(&why);
  if (!a.no_window && !p.window && std::getenv("DISPLAY") != nullptr && !a.quiet)
    std::cerr << "live: no window (" << why << "); the status line follows, --overlay writes the view\n";
  p.quiet = a.quiet;
  runPipeline(sequence, p);
}

}  // namespace

void registerLiveCommand(CLI::App& root) {
  auto args = std::make_shared<LiveArgs>();
  CLI::App* cmd = root.add_subcommand(
      "live",
      "Run odometry (or, without IMU, masking and tracking) live: --replay SEQ | --video FILE | --v4l2 DEV | --d435i");
  addLiveSourceOptions(cmd, args->source);
  cmd->add_option("--out", args->out_dir, "output folder (trajectory.tum, summary.yaml)")->capture_default_str();
  cmd->add_option("--config", args->config_path, "run config YAML (tracker:, estimator:, dynamic:, pipeline: maps)")
      ->check(CLI::ExistingFile);
  addMaskOptions(cmd, args->mask);
  cmd->add_option("--overlay", args->overlay,
                  "write the live view as a video (.avi or .mp4): mask tinted, boxes with ids, features kept (green) "
                  "and dropped as dynamic (red), status line, top view of the trajectory");
  cmd->add_flag("--no-window", args->no_window, "no window even when $DISPLAY is set");
  cmd->add_flag("-q,--quiet", args->quiet, "no status line on stderr");
  cmd->callback([args] { runLive(*args); });
}

}  // namespace adugs::app

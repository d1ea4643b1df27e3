// `adugs run`: plays a recorded sequence through an estimator and writes the trajectory, a run
// summary and, when ground truth is present, the evaluation (ATE, RPE, plot).
//
// Estimators:
//   vio       the visual-inertial odometry (the pipeline of app/pipeline/pipeline.h, app/run_pipeline.cpp)
//   imu-only  strapdown IMU dead reckoning started from the ground-truth state at the first
//             frame (needs ground truth). It is the baseline the visual-inertial estimator must
//             beat by orders of magnitude, and it exercises the whole pipeline: streaming reader,
//             per-frame flushed TUM output, evaluation.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/run_config.h"
#include "app/run_options.h"
#include "app/run_pipeline.h"
#include "app/run_report.h"
#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "data/sources/dataset_preset.h"
#include "vio/imu/imu_dead_reckoning.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct RunArgs {
  SequenceArgs sequence;
  std::string out_dir = "out/run";
  std::string estimator = "vio";
  std::string config_path;
  MaskArgs mask;
  std::string overlay;
  bool quiet = false;
};

void runImuOnly(const RunArgs& a) {
  data::PlaybackOptions playback = playbackOptions(a.sequence, a.config_path);
  playback.load_images = false;  // the imu-only estimator does not look at images
  data::OpenedSequence sequence = data::openSequence(playback, a.out_dir);
  data::SequenceSource& reader = *sequence.source;
  const std::string gt_path = sequence.gt_path;
  if (gt_path.empty())
    throw data::InputError(playback.path, 0, "ground truth",
                           "the imu-only estimator starts from the ground-truth state, and this "
                           "sequence has no ground truth (no mav0/state_groundtruth_estimate0 or "
                           "mocap0, no ground-truth topic; give one with --gt)");
  const auto gt_states = data::readGroundTruthStates(gt_path);

  fs::create_directories(a.out_dir);
  const std::string traj_path = (fs::path(a.out_dir) / "trajectory.tum").string();
  data::TumTrajectoryWriter writer(traj_path);
  vio::ImuDeadReckoning estimator(gt_states);

  RunStats stats;
  const auto wall_start = std::chrono::steady_clock::now();
  data::Measurement m;
  int64_t first_t = -1;
  while (reader.next(m)) {
    if (first_t < 0) first_t = m.timeNs();
    if (m.isImu()) {
      ++stats.imu_samples;
      estimator.addImu(m.imu);
      continue;
    }
    ++stats.frames;
    stats.sequence_s = data::nsToSec(m.frame.t_ns - first_t);
    if (const auto pose = estimator.poseAt(m.frame.t_ns)) {
      writer.write(*pose);
      ++stats.poses;
    }
    if (!a.quiet && stats.frames % 200 == 0)
      std::cerr << "run: " << stats.frames << " frames, " << stats.sequence_s << " s\n"
                << std::flush;
  }
  writer.close();
  stats.skipped_frames = reader.counts().skipped_frames;
  stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  writeRunOutputs(a.out_dir, "imu-only", traj_path, gt_path, stats);
}

void runSequence(const RunArgs& a) {
  if (a.estimator == "imu-only") {
    if (a.mask.masking.source != MaskSource::kNone || !a.config_path.empty())
      throw CLI::ValidationError("--mask/--config", "only the vio estimator uses them");
    runImuOnly(a);
    return;
  }
  data::OpenedSequence sequence = data::openSequence(playbackOptions(a.sequence, a.config_path), a.out_dir);
  PipelineRunArgs p;
  p.command = "run";
  p.out_dir = a.out_dir;
  p.config_path = a.config_path;
  p.mask = a.mask;
  p.overlay = a.overlay;
  p.quiet = a.quiet;
  runPipeline(sequence, p);
}

}  // namespace

void registerRunCommand(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = root.add_subcommand(
      "run", "Run odometry on a recorded sequence; writes trajectory.tum, summary and evaluation");
  addSequenceOptions(cmd, args->sequence);
  cmd->add_option("path", args->sequence.playback.path, "sequence folder (the folder holding mav0) or ROS1 bag file")
      ->required();
  cmd->add_flag("--realtime", args->sequence.playback.realtime, "pace the playback at sensor time");
  cmd->add_option("--out", args->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--estimator", args->estimator,
                  "vio: visual-inertial odometry; imu-only: IMU dead reckoning from the "
                  "ground-truth initial state (baseline)")
      ->check(CLI::IsMember({"vio", "imu-only"}))
      ->capture_default_str();
  cmd->add_option("--config", args->config_path, "run config YAML (tracker:, estimator: maps; see data/config/)")
      ->check(CLI::ExistingFile);
  addMaskOptions(cmd, args->mask);
  cmd->add_option("--overlay", args->overlay,
                  "write a video (.avi or .mp4) of every frame: dynamic mask tinted, boxes with ids, features kept "
                  "(green) and dropped as dynamic (red), a status line, the top view of the trajectory");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress on stderr");
  cmd->callback([args] { runSequence(*args); });
}

}  // namespace adugs::app

// `adugs run`: plays a recorded sequence through an estimator and writes the trajectory, a run
// summary and, when ground truth is present, the evaluation (ATE, RPE, plot).
//
// Estimators:
//   vio       the visual-inertial odometry (front-end + sliding-window estimator, app/run_vio.cpp)
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
#include "app/run_report.h"
#include "app/run_vio.h"
#include "data/dataset_preset.h"
#include "data/input_error.h"
#include "data/trajectory_io.h"
#include "vio/imu/imu_dead_reckoning.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct RunArgs {
  data::PlaybackOptions playback;
  double start_s = 0, duration_s = 0, reorder_window_s = 0.1;
  bool reorder_window_given = false;
  std::string out_dir = "out/run";
  std::string estimator = "vio";
  std::string config_path;
  std::string mask = "none";
  std::string detector_model, segmenter = "grabcut", sam_encoder, sam_decoder, detector_config;
  int detect_every = 0;  // 0: the run config's (default 1)
  std::string overlay;
  bool quiet = false;
};

// The command line's playback options over the config's `playback:` map over the preset.
data::PlaybackOptions playbackOptions(const RunArgs& a) {
  data::PlaybackOptions o = a.playback;
  o.start_ns = data::secToNs(a.start_s);
  o.duration_ns = data::secToNs(a.duration_s);
  o.reorder_window_ns = data::secToNs(a.reorder_window_s);
  if (!a.config_path.empty())
    applyPlaybackConfig(loadRunConfig(a.config_path).playback, a.reorder_window_given, &o);
  return o;
}

void runImuOnly(const RunArgs& a) {
  data::PlaybackOptions playback = playbackOptions(a);
  playback.load_images = false;  // the imu-only estimator does not look at images
  data::OpenedSequence sequence = data::openSequence(playback, a.out_dir);
  data::SequenceSource& reader = *sequence.source;
  const std::string gt_path = sequence.gt_path;
  if (gt_path.empty())
    throw data::InputError(a.playback.path, 0, "ground truth",
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
    if (a.mask != "none" || !a.config_path.empty())
      throw CLI::ValidationError("--mask/--config", "only the vio estimator uses them");
    runImuOnly(a);
    return;
  }
  VioRunArgs v;
  v.playback = playbackOptions(a);
  v.out_dir = a.out_dir;
  v.config_path = a.config_path;
  v.mask = a.mask;
  v.detector_model = a.detector_model;
  v.detector_config = a.detector_config;
  v.segmenter = a.segmenter;
  v.sam_encoder = a.sam_encoder;
  v.sam_decoder = a.sam_decoder;
  v.detect_every = a.detect_every;
  v.overlay = a.overlay;
  v.quiet = a.quiet;
  runVio(v);
}

}  // namespace

void registerRunCommand(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = root.add_subcommand(
      "run", "Run odometry on a recorded sequence; writes trajectory.tum, summary and evaluation");
  data::PlaybackOptions& p = args->playback;
  cmd->add_option("--dataset", p.dataset,
                  "sequence format and preset: euroc (ASL folder), tum-vi (folder), euroc-bag, "
                  "viode, openloris (ROS1 bags), bag (any ROS1 bag: give topics and Kalibr files)")
      ->check(CLI::IsMember(data::datasetPresetNames()))
      ->capture_default_str();
  cmd->add_option("path", p.path, "sequence folder (the folder holding mav0) or ROS1 bag file")
      ->required();
  cmd->add_option("--kalibr-camchain", p.kalibr_camchain,
                  "Kalibr camchain-imucam.yaml (cam0 intrinsics, T_cam_imu, timeshift_cam_imu); "
                  "replaces the preset's or the folder's camera calibration")
      ->check(CLI::ExistingFile);
  cmd->add_option("--kalibr-imu", p.kalibr_imu, "Kalibr imu.yaml (noise densities, random walks)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--image-topic", p.topics.image, "bag: image topic (Image or CompressedImage)");
  cmd->add_option("--imu-topic", p.topics.imu, "bag: sensor_msgs/Imu topic with both sensors");
  cmd->add_option("--accel-topic", p.topics.accel,
                  "bag: accelerometer topic (with --gyro-topic; united on the gyro stamps)");
  cmd->add_option("--gyro-topic", p.topics.gyro, "bag: gyroscope topic (with --accel-topic)");
  cmd->add_option("--gt-topic", p.gt_topic,
                  "bag: ground truth topic (Odometry, PoseStamped, TransformStamped or /tf)");
  cmd->add_option("--gt-parent-frame", p.gt_parent_frame, "bag: --gt-topic /tf: parent frame");
  cmd->add_option("--gt-child-frame", p.gt_child_frame, "bag: --gt-topic /tf: child frame");
  cmd->add_option("--reorder-window", args->reorder_window_s,
                  "bag: seconds messages are held to be put in header.stamp order")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--start", args->start_s, "start this many seconds into the sequence")
      ->check(CLI::Range(0.0, 1e9));
  cmd->add_option("--duration", args->duration_s, "play this many seconds (0: to the end)")
      ->check(CLI::Range(0.0, 1e9));
  cmd->add_flag("--realtime", p.realtime, "pace the playback at sensor time");
  cmd->add_option("--out", args->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--gt", p.gt_path,
                  "ground truth file (EuRoC CSV or TUM); default: the folder's "
                  "state_groundtruth_estimate0 / mocap0, or the preset's ground-truth topic")
      ->check(CLI::ExistingFile);
  cmd->add_option("--estimator", args->estimator,
                  "vio: visual-inertial odometry; imu-only: IMU dead reckoning from the "
                  "ground-truth initial state (baseline)")
      ->check(CLI::IsMember({"vio", "imu-only"}))
      ->capture_default_str();
  cmd->add_option("--config", args->config_path,
                  "run config YAML (tracker:, estimator: maps; see data/config/)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--mask", args->mask,
                  "dynamic mask per frame: none; gt = the simulator's mav0/mask0 masks; detector = "
                  "detector -> SORT -> box segmentation -> refinement")
      ->check(CLI::IsMember({"none", "gt", "detector"}))
      ->capture_default_str();
  cmd->add_option("--detector-config", args->detector_config,
                  "--mask detector: darknet .cfg (default: beside the .weights)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detector-model", args->detector_model,
                  "--mask detector: ultralytics .torchscript, ultralytics/YOLOX .onnx or darknet .weights model")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detect-every", args->detect_every,
                  "--mask detector: run the detector on every n-th frame; SORT's predictions carry the boxes between "
                  "(default: the run config's dynamic: detect_every, 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--overlay", args->overlay,
                  "write a video (.avi or .mp4) of every frame: dynamic mask tinted, boxes with ids, features kept "
                  "(green) and dropped as dynamic (red), a status line");
  cmd->add_option("--segmenter", args->segmenter, "--mask detector: box segmenter")
      ->check(CLI::IsMember({"grabcut", "box", "mobilesam"}))
      ->capture_default_str();
  cmd->add_option("--sam-encoder", args->sam_encoder, "--segmenter mobilesam: mobilesam_encoder.pt (scripts/export_mobilesam.py)");
  cmd->add_option("--sam-decoder", args->sam_decoder, "--segmenter mobilesam: mobilesam_decoder.pt (scripts/export_mobilesam.py)");
  cmd->add_flag("--skip-bad-frames", p.skip_bad_frames,
                "skip missing or corrupt images with a warning instead of stopping");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress on stderr");
  CLI::Option* window = cmd->get_option("--reorder-window");
  cmd->callback([args, window] {
    args->reorder_window_given = window->count() > 0;
    runSequence(*args);
  });
}

}  // namespace adugs::app

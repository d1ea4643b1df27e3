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
#include "app/run_report.h"
#include "app/run_vio.h"
#include "data/euroc_reader.h"
#include "data/input_error.h"
#include "data/trajectory_io.h"
#include "vio/imu_dead_reckoning.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct RunArgs {
  std::string dataset = "euroc";
  std::string path;
  std::string out_dir = "out/run";
  std::string estimator = "vio";
  std::string config_path;
  std::string mask = "none";
  std::string detector_model, segmenter = "grabcut", sam_encoder, sam_decoder;
  std::string gt_path;  // overrides mav0/state_groundtruth_estimate0/data.csv
  bool skip_bad_frames = false;
  bool quiet = false;
};

void runImuOnly(const RunArgs& a) {
  data::EurocReaderOptions reader_options;
  reader_options.skip_bad_frames = a.skip_bad_frames;
  reader_options.load_images = false;  // the imu-only estimator does not look at images
  data::EurocReader reader(a.path, reader_options);
  const std::string gt_path = a.gt_path.empty() ? reader.groundTruthPath() : a.gt_path;
  if (gt_path.empty())
    throw data::InputError(reader.mavDir(), 0, "state_groundtruth_estimate0",
                           "the imu-only estimator starts from the ground-truth state, and this "
                           "sequence has no ground truth (give one with --gt)");
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
  stats.skipped_frames = reader.skippedFrames();
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
  v.path = a.path;
  v.out_dir = a.out_dir;
  v.gt_path = a.gt_path;
  v.config_path = a.config_path;
  v.mask = a.mask;
  v.detector_model = a.detector_model;
  v.segmenter = a.segmenter;
  v.sam_encoder = a.sam_encoder;
  v.sam_decoder = a.sam_decoder;
  v.skip_bad_frames = a.skip_bad_frames;
  v.quiet = a.quiet;
  runVio(v);
}

}  // namespace

void registerRunCommand(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = root.add_subcommand(
      "run", "Run odometry on a recorded sequence; writes trajectory.tum, summary and evaluation");
  cmd->add_option("--dataset", args->dataset, "sequence format")
      ->check(CLI::IsMember({"euroc"}))
      ->capture_default_str();
  cmd->add_option("path", args->path, "sequence folder (EuRoC ASL: the folder holding mav0)")
      ->required();
  cmd->add_option("--out", args->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--gt", args->gt_path,
                  "ground truth (EuRoC CSV or TUM) if not mav0/state_groundtruth_estimate0")
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
                  "YOLOX -> SORT -> box segmentation -> refinement")
      ->check(CLI::IsMember({"none", "gt", "detector"}))
      ->capture_default_str();
  cmd->add_option("--detector-model", args->detector_model, "--mask detector: YOLOX ONNX model")
      ->check(CLI::ExistingFile);
  cmd->add_option("--segmenter", args->segmenter, "--mask detector: box segmenter")
      ->check(CLI::IsMember({"grabcut", "box", "mobilesam"}))
      ->capture_default_str();
  cmd->add_option("--sam-encoder", args->sam_encoder, "--segmenter mobilesam: image encoder ONNX");
  cmd->add_option("--sam-decoder", args->sam_decoder, "--segmenter mobilesam: prompt decoder ONNX");
  cmd->add_flag("--skip-bad-frames", args->skip_bad_frames,
                "skip missing or corrupt images with a warning instead of stopping");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress on stderr");
  cmd->callback([args] { runSequence(*args); });
}

}  // namespace adugs::app

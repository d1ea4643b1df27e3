#include "app/run_options.h"

#include "app/run_config.h"

namespace adugs::app {

void addSequenceOptions(CLI::App* cmd, SequenceArgs& args) {
  data::PlaybackOptions& p = args.playback;
  cmd->add_option("--dataset", p.dataset,
                  "sequence format and preset: euroc (ASL folder), tum-vi (folder), euroc-bag, "
                  "viode, openloris (ROS1 bags), bag (any ROS1 bag: give topics and Kalibr files)")
      ->check(CLI::IsMember(data::datasetPresetNames()))
      ->capture_default_str();
  cmd->add_option("--calibration", p.calibration,
                  "calibration files of any of Kalibr (camchain-imucam.yaml, imu.yaml), OpenVINS "
                  "(kalibr_imucam_chain.yaml, kalibr_imu_chain.yaml), VINS-Mono/Fusion (config.yaml, naming "
                  "its camera files), Basalt (calib.json), EuRoC (sensor.yaml); recognised by content; "
                  "they replace the preset's or the folder's calibration for what they give")
      ->check(CLI::ExistingFile)
      ->expected(1, -1);
  // The older spellings, kept as aliases: each adds its file to --calibration.
  cmd->add_option_function<std::string>(
         "--kalibr-camchain", [&p](const std::string& f) { p.calibration.push_back(f); },
         "Kalibr camchain-imucam.yaml (alias: adds the file to --calibration)")
      ->check(CLI::ExistingFile);
  cmd->add_option_function<std::string>(
         "--kalibr-imu", [&p](const std::string& f) { p.calibration.push_back(f); },
         "Kalibr imu.yaml (alias: adds the file to --calibration)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--image-topic", p.topics.image, "bag: image topic (Image or CompressedImage)");
  cmd->add_option("--imu-topic", p.topics.imu, "bag: sensor_msgs/Imu topic with both sensors");
  cmd->add_option("--accel-topic", p.topics.accel,
                  "bag: accelerometer topic (with --gyro-topic; united on the gyro stamps)");
  cmd->add_option("--gyro-topic", p.topics.gyro, "bag: gyroscope topic (with --accel-topic)");
  cmd->add_option("--gt-topic", p.gt_topic, "bag: ground truth topic (Odometry, PoseStamped, TransformStamped or /tf)");
  cmd->add_option("--gt-parent-frame", p.gt_parent_frame, "bag: --gt-topic /tf: parent frame");
  cmd->add_option("--gt-child-frame", p.gt_child_frame, "bag: --gt-topic /tf: child frame");
  args.reorder_window =
      cmd->add_option("--reorder-window", args.reorder_window_s, "bag: seconds messages are held to be put in header.stamp order")
          ->check(CLI::Range(0.0, 10.0))
          ->capture_default_str();
  cmd->add_option("--start", args.start_s, "start this many seconds into the sequence")->check(CLI::Range(0.0, 1e9));
  cmd->add_option("--duration", args.duration_s, "play this many seconds (0: to the end)")->check(CLI::Range(0.0, 1e9));
  cmd->add_option("--gt", p.gt_path,
                  "ground truth file (EuRoC CSV or TUM); default: the folder's "
                  "state_groundtruth_estimate0 / mocap0, or the preset's ground-truth topic")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--skip-bad-frames", p.skip_bad_frames, "skip missing or corrupt images with a warning instead of stopping");
}

data::PlaybackOptions playbackOptions(const SequenceArgs& a, const std::string& config_path) {
  data::PlaybackOptions o = a.playback;
  o.start_ns = data::secToNs(a.start_s);
  o.duration_ns = data::secToNs(a.duration_s);
  o.reorder_window_ns = data::secToNs(a.reorder_window_s);
  const bool window_given = a.reorder_window != nullptr && a.reorder_window->count() > 0;
  if (!config_path.empty()) applyPlaybackConfig(loadRunConfig(config_path).playback, window_given, &o);
  return o;
}

void addMaskOptions(CLI::App* cmd, MaskArgs& args) {
  MaskingOptions& m = args.masking;
  cmd->add_option("--mask", m.source,
                  "dynamic mask per frame: none; gt = the simulator's mav0/mask0 masks; detector = "
                  "detector (+ motion cue) -> SORT -> box segmentation -> refinement; motion = the same chain prompted "
                  "by the class-free motion cue alone (points moving against the camera's own motion; no model)")
      ->transform(CLI::CheckedTransformer(maskSourceNames()))
      ->default_str("none");
  cmd->add_option("--detector-config", m.detector_config, "--mask detector: darknet .cfg (default: beside the .weights)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detector-model", m.detector_model,
                  "--mask detector: ultralytics .torchscript, ultralytics/YOLOX .onnx or darknet .weights model")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detect-every", args.detect_every,
                  "--mask detector: run the detector on every n-th frame; SORT's predictions carry the boxes between "
                  "(default: the run config's dynamic: detect_every, 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--motion-cue,!--no-motion-cue", m.motion_cue,
               "--mask detector: the motion cue's boxes beside the detector's (off until measured on Table I: "
               "doc/tracking.md)");
  cmd->add_option("--segmenter", m.segmenter, "--mask detector|motion: box segmenter")
      ->check(CLI::IsMember({"grabcut", "box", "mobilesam"}))
      ->capture_default_str();
  cmd->add_option("--sam-encoder", m.sam_encoder, "--segmenter mobilesam: mobilesam_encoder.pt (scripts/export_mobilesam.py)");
  cmd->add_option("--sam-decoder", m.sam_decoder, "--segmenter mobilesam: mobilesam_decoder.pt (scripts/export_mobilesam.py)");
}

}  // namespace adugs::app

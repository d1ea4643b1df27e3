#pragma once
// The configuration of `adugs run --config FILE` (data/config/*.yaml): one map per stage,
//   tracker:   vio/frontend/feature_tracker_options.h keys
//   estimator: vio/estimator/estimator_options.h keys (static_init:, init: nested)
//   dynamic:   the dynamic-object stage of --mask detector (tracking/dynamic_masker_options.h keys)
//   pipeline:  frame_queue (frames that may wait at the pipeline's entrance; live sources drop the
//              oldest beyond it), test_estimator_delay_ms (FOR TESTS ONLY: a sleep per frame in the
//              estimator stage, to check the live drop policy with an estimator slower than the camera)
//   playback:  bag topics and the reorder window (image_topic, imu_topic, accel_topic,
//              gyro_topic, gt_topic, gt_parent_frame, gt_child_frame, reorder_window_s); the
//              command line's options win over these, these over the --dataset preset
//   d435i:     the RealSense D435i live source (data/sources/d435i_options.h: streams, controls, IMU
//              rates, the default cam0 / imu0 calibration in Kalibr spelling); read by
//              `adugs live --d435i` and `adugs record --d435i`, ignored by `adugs run`
// Every key is optional; unknown keys and out-of-range values are errors naming file, line, key.
#include <string>

#include "data/sources/d435i_options.h"
#include "data/sources/dataset_preset.h"
#include "tracking/dynamic_masker_options.h"
#include "vio/estimator/estimator_options.h"
#include "vio/frontend/feature_tracker_options.h"

namespace adugs::app {

struct PipelineConfig {
  int frame_queue = 2;
  double test_estimator_delay_ms = 0;
};

struct RunConfig {
  vio::FeatureTrackerOptions tracker;
  vio::EstimatorOptions estimator;
  tracking::DynamicMaskerOptions dynamic;
  PipelineConfig pipeline;
  data::PlaybackOptions playback;  // only the topic / frame / window fields are read
  data::D435iOptions d435i;
};

// Fills the playback fields the command line left empty (or at their default) from the config.
void applyPlaybackConfig(const data::PlaybackOptions& config, bool window_given, data::PlaybackOptions* options);

RunConfig loadRunConfig(const std::string& path);  // "" = the defaults in code

// The config `adugs run` / `adugs live` use without --config: one per sensor class in data/config/
// (built into the binary), chosen from what the sequence says about its camera:
//   sim.yaml    a folder written by `adugs sim` with a simulated IMU (its camera has EuRoC's lens
//               distortion, so only the folder tells), or a camera below 25 Hz without lens
//               distortion (rendered images: VIODE) unless the folder is a hybrid one of `adugs
//               sim` (rendered along a real flight's IMU: euroc.yaml, the real IMU's settings)
//   d435i.yaml  a camera at 25 Hz or more (RealSense D435i: 30 Hz; td estimated online)
//   euroc.yaml  below 25 Hz with lens distortion (EuRoC, TUM-VI), or rate unknown
struct RunConfigChoice {
  std::string name;    // file name in data/config/
  std::string reason;  // why, for the start-of-run line and the summary
};
RunConfigChoice chooseRunConfig(const data::CameraCalibration& camera, data::SimFolder folder);
// The user's --config file when given, else the sensor class's built-in one; `described` says
// which (and why) for the start-of-run line and the summary.
RunConfig runConfigFor(const std::string& config_path, const data::OpenedSequence& sequence, std::string* described);

}  // namespace adugs::app

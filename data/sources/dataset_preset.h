#pragma once
// Opening a recorded sequence the way `adugs run --dataset NAME PATH` asks for it.
//
// Presets (topics and calibration for the public datasets; every field can be overridden):
//   euroc      EuRoC ASL folder (mav0/cam0, imu0, state_groundtruth_estimate0); its sensor.yaml
//   euroc-bag  EuRoC ROS bag: /cam0/image_raw (mono8), /imu0; calibration: EuRoC's cam0/imu0
//   tum-vi     TUM-VI folder (ASL layout, 16-bit PNGs in the _16 sets, mocap0 ground truth);
//              calibration: TUM-VI's published 512x512 equidistant cam0
//   viode      VIODE bag: /cam0/image_raw (bgr8), /imu0, ground truth /odometry (nav_msgs/Odometry)
//   openloris  OpenLORIS-Scene bag: /d400/color/image_raw, /d400/accel/sample + /d400/gyro/sample;
//              ground truth: groundtruth.txt beside the bag (TUM), else the bag's /gt
//              (tf2 gt_map -> base_link) when it has one
//   bag        any ROS1 bag: give the topics and the Kalibr files
// The presets' calibration files are data/config/presets/NAME/{camchain-imucam,imu}.yaml, built
// into the binary. Kalibr files given by the user replace them.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/sources/rosbag_source.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

struct PlaybackOptions {
  std::string dataset = "euroc";
  std::string path;  // folder (euroc, tum-vi) or bag file
  RosbagTopics topics;  // empty fields: the preset's
  std::string gt_topic, gt_parent_frame, gt_child_frame;  // ground truth in the bag
  std::string gt_path;                                    // ground-truth file (TUM / EuRoC CSV)
  // The user's calibration files, any tool's (data/formats/calibration_files.h); they replace the
  // preset's or the folder's calibration for what they give.
  std::vector<std::string> calibration;
  int64_t reorder_window_ns = 100'000'000;
  bool skip_bad_frames = false;
  bool load_images = true;
  int64_t start_ns = 0, duration_ns = 0;  // --start / --duration (0 = to the end)
  bool realtime = false;                  // pace at sensor time
};

class YamlOptionsReader;
// The `playback:` map of a run config: image_topic, imu_topic, accel_topic, gyro_topic,
// gt_topic, gt_parent_frame, gt_child_frame, reorder_window_s (the other fields are the command
// line's). Errors name file, line and key.
void readPlaybackConfig(YamlOptionsReader& r, PlaybackOptions* options);

// How a folder was made, for the run config's sensor class: not by `adugs sim`; by it with a
// simulated IMU (mode: synthetic); or rendered along a real flight's IMU (mode: hybrid).
enum class SimFolder { kNone, kSynthetic, kHybrid };

struct OpenedSequence {
  std::unique_ptr<SequenceSource> source;
  CameraCalibration camera;
  ImuNoise imu_noise;
  bool has_imu = true;   // false: a camera alone (video, webcam): vision only, no odometry
  std::string gt_path;   // ground-truth file to evaluate against ("" if none)
  std::string mask_dir;  // the simulator's per-frame dynamic masks (ASL folders only; "" if none)
  std::string objects_path;  // beside them, the movers' boxes with their classes (mav0/objects0/gt.txt)
  // What mav0/sim.yaml says of a folder written by `adugs sim` (its `mode:`).
  SimFolder sim_folder = SimFolder::kNone;
  std::string calibration_from;  // where the calibration came from, for the run summary
  // Calibration files it was read from that may carry adugs calib's verdict: the user's Kalibr
  // files, an ASL folder's own cam0/sensor.yaml.
  std::vector<std::string> calibration_files;
  size_t gt_duplicates_dropped = 0;
};

// The names accepted by --dataset.
std::vector<std::string> datasetPresetNames();

// Opens the sequence; ground truth found in a bag is written to out_dir/groundtruth.tum.
OpenedSequence openSequence(const PlaybackOptions& options, const std::string& out_dir);

// The built-in text of data/config/presets/PRESET/FILE ("" if there is none).
std::string presetCalibrationText(const std::string& preset, const std::string& file);

}  // namespace adugs::data

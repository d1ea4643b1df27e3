#include "data/sources/dataset_preset.h"

#include <filesystem>
#include <iostream>

#include "data/builtin_config.h"
#include "data/formats/calibration_files.h"
#include "data/formats/kalibr_calibration.h"
#include "data/formats/trajectory_io.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "data/sources/euroc_reader.h"
#include "data/sources/imu_correction.h"
#include "data/sources/playback_controls.h"
#include "data/sources/rosbag_ground_truth.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

struct Preset {
  const char* name;
  bool bag;
  RosbagTopics topics;
  const char* gt_topic;  // used when the bag has it (a user's --gt-topic must exist)
  const char* gt_parent;
  const char* gt_child;
  const char* gt_file_beside;  // a ground-truth file shipped beside the bag, used before the topic
  const char* calibration;  // folder under data/config/presets, "" = the sequence's own files
};

const std::vector<Preset>& presets() {
  static const std::vector<Preset> table = {
      {"euroc", false, {}, "", "", "", "", ""},
      {"euroc-bag", true, {"/cam0/image_raw", "/imu0", "", ""}, "", "", "", "", "euroc"},
      {"tum-vi", false, {}, "", "", "", "", "tum-vi"},
      {"viode", true, {"/cam0/image_raw", "/imu0", "", ""}, "/odometry", "", "", "", "viode"},
      // OpenLORIS: groundtruth.txt beside the bag, else the merged bags' /gt (gt_map -> base_link).
      {"openloris", true, {"/d400/color/image_raw", "", "/d400/accel/sample", "/d400/gyro/sample"}, "/gt",
       "gt_map", "base_link", "groundtruth.txt", "openloris"},
      {"bag", true, {}, "", "", "", "", ""},
  };
  return table;
}

const Preset& findPreset(const std::string& name) {
  for (const Preset& p : presets())
    if (name == p.name) return p;
  std::string known;
  for (const Preset& p : presets()) known += (known.empty() ? "" : ", ") + std::string(p.name);
  throw InputError("--dataset", 0, "dataset", "unknown dataset '" + name + "' (known: " + known + ")");
}

std::string pick(const std::string& user, const std::string& preset) { return user.empty() ? preset : user; }

struct Calibration {
  std::optional<RigCamera> camera;
  std::optional<RigImu> imu;
  std::string from;
  std::vector<std::string> user_files;
};

// The user's calibration files first (any tool's, data/formats/calibration_files.h), then the
// preset's built-in Kalibr files for what they do not give.
Calibration loadCalibration(const PlaybackOptions& o, const Preset& preset) {
  Calibration c;
  std::string camera_from, imu_from;
  if (!o.calibration.empty()) {
    const RigCalibration rig = readCalibrationFiles(o.calibration);
    reportIgnoredKeys(rig, std::cerr);
    if (!rig.cameras.empty()) {
      c.camera = rig.cameras.front();
      camera_from = c.camera->source;
    }
    if (rig.has_imu) {
      c.imu = rig.imu;
      imu_from = rig.imu.source;
    }
    c.user_files = rig.files;
  }
  if (!c.camera && *preset.calibration) {
    const std::string name = std::string("preset ") + preset.calibration + " camchain-imucam.yaml";
    c.camera = parseKalibrCamchain(presetCalibrationText(preset.calibration, "camchain-imucam.yaml"), name);
    camera_from = name;
  }
  if (!c.imu && *preset.calibration) {
    const std::string name = std::string("preset ") + preset.calibration + " imu.yaml";
    c.imu = parseKalibrImu(presetCalibrationText(preset.calibration, "imu.yaml"), name);
    imu_from = name;
  }
  if (c.camera && !c.camera->has_T_imu_cam)
    throw InputError(camera_from, 0, "cam0.T_cam_imu",
                     "the camera-IMU extrinsic is missing (a camchain-imucam.yaml from Kalibr's "
                     "camera-IMU calibration has it)");
  c.from = "camera: " + (camera_from.empty() ? "sequence" : camera_from) +
           ", imu: " + (imu_from.empty() ? "sequence" : imu_from);
  return c;
}

// VINS' per-sample noise becomes densities at the sequence's IMU rate.
ImuNoise noiseAt(RigImu imu, double sequence_rate_hz) {
  if (imu.noise_per_sample) {
    const double rate = imu.noise.rate_hz > 0 ? imu.noise.rate_hz : sequence_rate_hz;
    if (!(rate > 0))
      throw InputError(imu.source, 0, "acc_n",
                       "VINS' noise figures are per IMU sample and this sequence does not say its IMU rate: "
                       "give a Kalibr imu file with update_rate as well");
    resolvePerSampleNoise(imu, rate);
  }
  return imu.noise;
}

OpenedSequence openFolder(const PlaybackOptions& o, const Calibration& calib) {
  OpenedSequence s;
  EurocReaderOptions ro;
  ro.skip_bad_frames = o.skip_bad_frames;
  ro.load_images = o.load_images;
  EurocCalibrationOverride override;
  if (calib.camera) {
    override.camera = calib.camera->camera;
    override.image_time_shift_ns = secToNs(calib.camera->time_offset_s);
  }
  if (calib.imu && !calib.imu->noise_per_sample) override.imu_noise = calib.imu->noise;
  auto reader = std::make_unique<EurocReader>(o.path, ro, override);
  s.camera = reader->camera();
  s.imu_noise = calib.imu ? noiseAt(*calib.imu, reader->imuNoise().rate_hz) : reader->imuNoise();
  s.gt_path = o.gt_path.empty() ? reader->groundTruthPath() : o.gt_path;
  const fs::path masks = fs::path(reader->mavDir()) / "mask0" / "data";
  std::error_code ec;
  if (fs::is_directory(masks, ec)) s.mask_dir = masks.string();
  const fs::path objects = fs::path(reader->mavDir()) / "objects0" / "gt.txt";
  if (!s.mask_dir.empty() && fs::is_regular_file(objects, ec)) s.objects_path = objects.string();
  const fs::path sim = fs::path(reader->mavDir()) / "sim.yaml";
  if (fs::is_regular_file(sim, ec)) {
    // Only the mode matters here; the other keys (scene, seed, ...) describe how it was made.
    std::string mode;
    YamlOptionsReader::fromFile(sim.string()).optional("mode", mode);
    if (mode == "synthetic") s.sim_folder = SimFolder::kSynthetic;
    if (mode == "hybrid") s.sim_folder = SimFolder::kHybrid;
  }
  // The folder's own camera file may carry adugs calib's verdict (a recording made with a weak one).
  const fs::path camera_file = fs::path(reader->mavDir()) / "cam0" / "sensor.yaml";
  if (!calib.camera && fs::is_regular_file(camera_file, ec)) s.calibration_files.push_back(camera_file.string());
  s.source = std::move(reader);
  return s;
}

OpenedSequence openBagSequence(const PlaybackOptions& o, const Preset& preset, const Calibration& calib,
                               const std::string& out_dir) {
  if (!calib.camera || !calib.imu)
    throw InputError(o.path, 0, "--calibration",
                     "a bag carries no calibration: give --calibration with the camera and IMU files (Kalibr, "
                     "OpenVINS, VINS, Basalt), or a --dataset preset that has one");
  OpenedSequence s;
  s.camera = calib.camera->camera;
  s.imu_noise = noiseAt(*calib.imu, 0);
  RosbagSourceOptions ro;
  ro.topics.image = pick(o.topics.image, preset.topics.image);
  // One IMU topic or two: the user's choice wins over the preset's layout.
  const bool user_split = !o.topics.accel.empty() || !o.topics.gyro.empty();
  if (user_split) {
    ro.topics.accel = o.topics.accel;
    ro.topics.gyro = o.topics.gyro;
  } else if (!o.topics.imu.empty()) {
    ro.topics.imu = o.topics.imu;
  } else {
    ro.topics.imu = preset.topics.imu;
    ro.topics.accel = preset.topics.accel;
    ro.topics.gyro = preset.topics.gyro;
  }
  if (ro.topics.image.empty()) ro.topics.image = calib.camera->rostopic;
  if (ro.topics.imu.empty() && ro.topics.accel.empty()) ro.topics.imu = calib.imu->rostopic;
  ro.reorder_window_ns = o.reorder_window_ns;
  ro.load_images = o.load_images;
  ro.expected_width = s.camera.width;
  ro.expected_height = s.camera.height;
  ro.image_time_shift_ns = secToNs(calib.camera->time_offset_s);
  auto source = std::make_unique<RosbagSource>(o.path, ro);
  if (!(s.camera.rate_hz > 0)) s.camera.rate_hz = source->imageRateHz();  // Kalibr files rarely give it

  // Ground truth: --gt, else the user's --gt-topic, else the preset's file beside the bag, else
  // the preset's topic if this bag has it.
  BagGroundTruthOptions gt_options{o.gt_topic, o.gt_parent_frame, o.gt_child_frame};
  if (gt_options.topic.empty() && source->topics().count(preset.gt_topic))
    gt_options = {preset.gt_topic, pick(o.gt_parent_frame, preset.gt_parent), pick(o.gt_child_frame, preset.gt_child)};
  const fs::path beside = fs::path(o.path).parent_path() / preset.gt_file_beside;
  std::error_code ec;
  s.source = std::move(source);
  if (!o.gt_path.empty()) {
    s.gt_path = o.gt_path;
  } else if (*preset.gt_file_beside && o.gt_topic.empty() && fs::is_regular_file(beside, ec)) {
    s.gt_path = beside.string();
  } else if (!gt_options.topic.empty()) {
    const BagGroundTruth gt = readBagGroundTruth(o.path, gt_options);
    fs::create_directories(out_dir);
    s.gt_path = (fs::path(out_dir) / "groundtruth.tum").string();
    writeTumTrajectory(s.gt_path, gt.poses);
    s.gt_duplicates_dropped = gt.duplicates_dropped;
  }
  return s;
}

}  // namespace

std::string presetCalibrationText(const std::string& preset, const std::string& file) {
  return builtinConfigText("presets/" + preset + "/" + file);
}

void readPlaybackConfig(YamlOptionsReader& p, PlaybackOptions* options) {
  PlaybackOptions& o = *options;
  p.optional("image_topic", o.topics.image);
  p.optional("imu_topic", o.topics.imu);
  p.optional("accel_topic", o.topics.accel);
  p.optional("gyro_topic", o.topics.gyro);
  p.optional("gt_topic", o.gt_topic);
  p.optional("gt_parent_frame", o.gt_parent_frame);
  p.optional("gt_child_frame", o.gt_child_frame);
  double window_s = nsToSec(o.reorder_window_ns);
  p.optional("reorder_window_s", window_s, 0.0, 10.0);
  o.reorder_window_ns = secToNs(window_s);
}

std::vector<std::string> datasetPresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : presets()) names.push_back(p.name);
  return names;
}

OpenedSequence openSequence(const PlaybackOptions& o, const std::string& out_dir) {
  const Preset& preset = findPreset(o.dataset);
  const Calibration calib = loadCalibration(o, preset);
  OpenedSequence s = preset.bag ? openBagSequence(o, preset, calib, out_dir) : openFolder(o, calib);
  if (calib.imu) s.source = correctImu(std::move(s.source), calib.imu->intrinsics);
  s.calibration_from = calib.from;
  s.calibration_files.insert(s.calibration_files.end(), calib.user_files.begin(), calib.user_files.end());
  if (o.start_ns < 0 || o.duration_ns < 0)
    throw InputError("--start/--duration", 0, "start", "must not be negative");
  if (o.start_ns > 0 || o.duration_ns > 0 || o.realtime)
    s.source = std::make_unique<PlaybackControls>(std::move(s.source), o.start_ns, o.duration_ns, o.realtime);
  return s;
}

}  // namespace adugs::data

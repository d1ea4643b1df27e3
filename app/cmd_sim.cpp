// `adugs sim`: synthetic dynamic-scene sequences with exact ground truth (EuRoC ASL folder + masks
// + MOT boxes). `--level all` writes the four levels of one scene and seed side by side.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "data/input_error.h"
#include "data/sim/sim_sequence.h"

namespace adugs::app {
namespace {

struct SimArgs {
  data::SimSequenceOptions options;
  std::string level = "high";
  std::string out;
  bool no_imu_noise = false;
  std::vector<double> accel_bias;  // x y z, m/s^2
};

void runSim(SimArgs& a) {
  data::SimSequenceOptions o = a.options;
  o.imu.noise = !a.no_imu_noise;
  if (!a.accel_bias.empty()) {
    if (data::isHybrid(o))
      throw data::InputError("command line", 0, "--accel-bias", "a hybrid sequence keeps the real IMU's own bias");
    for (double b : a.accel_bias)
      if (!(std::abs(b) <= 10.0))  // also NaN
        throw data::InputError("command line", 0, "--accel-bias", "each value must be finite and within +-10 m/s^2");
    o.imu.initial_accel_bias = Eigen::Vector3d(a.accel_bias[0], a.accel_bias[1], a.accel_bias[2]);
  }
  std::vector<data::SimLevel> levels;
  if (a.level == "all")
    levels = {data::SimLevel::kNone, data::SimLevel::kLow, data::SimLevel::kMid, data::SimLevel::kHigh};
  else
    levels = {data::parseSimLevel(a.level, "--level")};
  data::checkSimSceneName(o.scene);
  for (data::SimLevel level : levels) {
    o.level = level;
    const std::string dir =
        a.level == "all" ? (std::filesystem::path(a.out) / data::toString(level)).string() : a.out;
    data::generateSimSequence(o, dir);
    std::cout << "adugs sim: wrote " << dir << " (" << o.scene << ", level " << data::toString(level)
              << ", seed " << o.seed << (data::isHybrid(o) ? ", hybrid" : "") << ")\n";
  }
}

}  // namespace

void registerSimCommand(CLI::App& root) {
  auto a = std::make_shared<SimArgs>();
  data::SimSequenceOptions& o = a->options;
  CLI::App* cmd = root.add_subcommand(
      "sim", "Generate synthetic dynamic-scene sequences with ground truth (EuRoC ASL + masks + MOT)");
  cmd->add_option("--out", a->out, "output folder (gets mav0/; with --level all, one folder per level)")
      ->required();
  cmd->add_option("--scene", o.scene, "world: room, street or courtyard (open square: far walls, low texture)")->capture_default_str();
  cmd->add_option("--motion", o.motion,
                  "how the rig moves: glide (smooth, vehicle-like) or handheld (walking: step bob and sway)")
      ->capture_default_str();
  cmd->add_option("--level", a->level, "moving objects: none, low, mid, high or all")
      ->capture_default_str();
  cmd->add_option("--people", o.people,
                  "how people look: boxes (textured boxes) or walkers (cut-outs of real walking people that "
                  "detectors recognise)")
      ->check(CLI::IsMember({"boxes", "walkers"}))
      ->capture_default_str();
  cmd->add_option("--standing", o.standing,
                  "people standing still, and in the street as many cars parked at the kerbs: of the detector's "
                  "classes but static, so not in the exact masks (objects0/gt.txt: conf 0, MOTChallenge's ignore)")
      ->capture_default_str();
  cmd->add_option("--walkers", o.walkers_dir, "--people walkers: sprite folder (default: the one the build cut)");
  cmd->add_option("--seed", o.seed, "random seed (world, path, objects, noise)")->capture_default_str();
  cmd->add_option("--duration", o.duration_s,
                  "seconds (hybrid: from the trajectory start; <= 0 = whole trajectory)")
      ->capture_default_str();
  cmd->add_option("--rate", o.camera_rate_hz, "camera rate [Hz] (hybrid: from --calib)")
      ->capture_default_str();
  cmd->add_option("--imu-rate", o.imu.rate_hz, "simulated IMU rate [Hz]")->capture_default_str();
  cmd->add_flag("--no-imu-noise", a->no_imu_noise, "exact IMU: no white noise, constant biases");
  cmd->add_option("--accel-bias", a->accel_bias,
                  "accelerometer turn-on bias X Y Z [m/s^2] (default 0 0 0); it random-walks from there")
      ->expected(3)
      ->delimiter(',');
  cmd->add_option("--time-offset", o.time_offset_s,
                  "camera-IMU time shift [s], Kalibr timeshift_cam_imu (t_imu = t_cam + shift)")
      ->capture_default_str();
  cmd->add_option("--pixel-noise", o.pixel_noise_sigma, "Gaussian pixel noise sigma [grey levels]")
      ->capture_default_str();
  cmd->add_option("--exposure-variation", o.exposure_variation,
                  "relative amplitude of auto-exposure gain changes (e.g. 0.2)")
      ->capture_default_str();
  cmd->add_option("--vignetting", o.vignetting,
                  "light lost in the image corner farthest from the principal point (0.3 = 30 % darker), falling off with the squared distance")
      ->capture_default_str();
  cmd->add_option("--blur-samples", o.blur_samples, "motion blur: renders averaged per frame (1 = off)")
      ->capture_default_str();
  cmd->add_option("--exposure-ms", o.exposure_ms, "motion blur: exposure time [ms]")->capture_default_str();
  cmd->add_option("--camera", o.camera_path,
                  "synthetic: render through this calibration's (first) camera: a cam0/sensor.yaml "
                  "(projection pinhole|omni|ds|eucm, distortion_model radial-tangential|equidistant|none) "
                  "or any file `adugs calib show` reads (Kalibr, OpenVINS, VINS, Basalt); default: EuRoC's cam0");
  cmd->add_option("--trajectory", o.trajectory_path,
                  "hybrid: EuRoC ground-truth CSV to follow (body = IMU frame)");
  cmd->add_option("--imu", o.imu_path, "hybrid: real EuRoC imu0/data.csv to keep");
  cmd->add_option("--calib", o.calib_path, "hybrid: EuRoC cam0/sensor.yaml (intrinsics, T_BS)");
  cmd->add_option("--imu-calib", o.imu_calib_path,
                  "imu0/sensor.yaml noise figures: hybrid, of the real IMU (default: next to "
                  "--imu); synthetic, the noise to simulate (default: EuRoC's ADIS16448)");
  cmd->callback([a] { runSim(*a); });
}

}  // namespace adugs::app

#pragma once
// `adugs sim` end to end: builds the trajectory, the IMU stream, the world and its moving objects,
// renders every frame and writes the EuRoC folder with masks and object boxes.
//   synthetic: scene + level + seed -> camera path (sum of sines), IMU from its exact derivatives
//   hybrid:    a given EuRoC ground truth + real IMU stream + cam0 calibration; the world is built
//              around the given path and rendered at T_W_B(t) * T_B_C.
#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "data/sim/sim_camera.h"
#include "data/sim/sim_imu.h"
#include "data/sim/sim_scene.h"

namespace adugs::data {

// 2023-11-14: an epoch-sized start so that stamps look like real recordings.
constexpr int64_t kSimDefaultStartNs = 1700000000000000000;

struct SimSequenceOptions {
  std::string scene = "room";
  std::string motion = "glide";  // synthetic mode: "glide" or "handheld" (see makeSceneTrajectory)
  SimLevel level = SimLevel::kHigh;
  uint64_t seed = 0;
  double duration_s = 60.0;  // hybrid: <= 0 means the whole given trajectory
  double camera_rate_hz = 20.0;
  int64_t start_ns = kSimDefaultStartNs;
  SimCamera camera;  // synthetic mode; hybrid takes it from calib_path
  // Synthetic mode: a cam0/sensor.yaml whose lens (resolution, intrinsics, projection,
  // distortion) replaces `camera`; its T_BS and rate are not used ("" = keep `camera`).
  std::string camera_path;
  Eigen::Isometry3d T_B_C = defaultSimT_B_C();
  // Kalibr's timeshift_cam_imu: an image stamped t_cam was exposed at IMU time t_cam + offset.
  double time_offset_s = 0.0;
  SimImuOptions imu;  // its seed is replaced by `seed`
  double pixel_noise_sigma = 1.0;   // grey levels
  double exposure_variation = 0.0;  // relative amplitude of slow auto-exposure changes
  double vignetting = 0.0;          // light lost in the farthest image corner (SimRenderOptions)
  int blur_samples = 1;             // > 1: motion blur over exposure_ms
  double exposure_ms = 0.0;
  // Hybrid mode (all three set): EuRoC ground-truth CSV, EuRoC imu0/data.csv, cam0/sensor.yaml.
  std::string trajectory_path, imu_path, calib_path;
  // Optional EuRoC imu0/sensor.yaml. Hybrid: the real IMU's figures (default: the sensor.yaml
  // next to imu_path). Synthetic: the noise densities and random walks to simulate with
  // (default: those in `imu`, EuRoC's ADIS16448); the rate stays imu.rate_hz.
  std::string imu_calib_path;
  // "boxes": people are textured boxes; "walkers": cut-outs of real walking people (detectors
  // recognise them), from walkers_dir ("" = defaultWalkersDir(), cut from vtest.avi at build time).
  std::string people = "boxes";
  std::string walkers_dir;
  // People standing still and, in the street, as many parked cars (addStandingObjects): objects
  // of the detector's classes that are not in the dynamic masks. 0 = none.
  int standing = 0;
  bool progress = true;        // progress lines on stderr
};

bool isHybrid(const SimSequenceOptions& options);

// Writes out_root/mav0/... Throws InputError for bad input (unreadable files, IMU not covering
// the trajectory, bad calibration, non-positive duration or rates).
void generateSimSequence(const SimSequenceOptions& options, const std::string& out_root);

}  // namespace adugs::data

#pragma once
// Synthetic camera-IMU recordings for the tests: a smooth IMU trajectory above an AprilGrid
// (data/sim/sim_trajectory), exact-derivative IMU with EuRoC noise (data/sim/sim_imu), and the board
// corners projected through a known T_C_I at t_imu = t_cam + shift, plus pixel noise.
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "calib/imu_noise/allan_variance.h"
#include "calib/kalibr_yaml.h"
#include "calib/target/aprilgrid.h"
#include "calib/target/target_observation.h"
#include "data/sim/sim_imu.h"
#include "data/sim/sim_trajectory.h"
#include "tests/calib/synthetic_views.h"

namespace adugs::calib::synth {

struct CameraImuRecording {
  AprilGrid grid;
  CalibCamera camera = eurocLikeCamera();
  Eigen::Isometry3d T_C_I = Eigen::Isometry3d::Identity();
  double shift_s = 0;
  std::vector<TargetObservation> views;
  ImuRecording imu;
  ImuNoiseFigures noise;
  Eigen::Vector3d gyro_bias{0.002, -0.003, 0.001};
  Eigen::Vector3d accel_bias{0.05, -0.03, 0.08};
};

inline AprilGrid eurocGrid() {
  AprilGrid g;
  g.tag_rows = 6;
  g.tag_cols = 6;
  g.tag_size_m = 0.088;
  g.tag_spacing = 0.3;
  return g;
}

// How the rig moves: everything (the calibration motion), planar (a ground robot: yaw only, the
// height fixed), or held still (one pose).
enum class RigMotion { kFull, kPlanar, kStill };

// duration_s of motion; camera at 20 Hz, IMU at 200 Hz; times start at start_ns.
inline CameraImuRecording makeCameraImuRecording(double duration_s, double shift_s,
                                                 double pixel_noise = 0.3, unsigned seed = 3,
                                                 int64_t start_ns = 1'000'000'000'000,
                                                 bool imu_noise = true,
                                                 RigMotion motion = RigMotion::kFull) {
  CameraImuRecording rec;
  rec.grid = eurocGrid();
  rec.shift_s = shift_s;
  // Camera looks down at the board (-z of the target), rotated 90 deg in the IMU as on EuRoC,
  // plus a few degrees of misalignment.
  rec.T_C_I.linear() = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                        Eigen::AngleAxisd(0.05, Eigen::Vector3d(1, 2, 3).normalized()))
                           .toRotationMatrix()
                           .transpose();
  rec.T_C_I.translation() = Eigen::Vector3d(0.04, -0.06, 0.015);

  using data::SineChannel;
  const double c = rec.grid.tag_cols * rec.grid.pitch() / 2;
  auto channel = [](double offset, double amp1, double f1, double amp2, double f2, double phase) {
    SineChannel ch;
    ch.offset = offset;
    ch.terms = {{amp1, f1, phase}, {amp2, f2, 0.7 * phase + 1}};
    return ch;
  };
  const int64_t end_ns = start_ns + static_cast<int64_t>(duration_s * 1e9);
  std::array<SineChannel, 6> channels = {
      channel(c, 0.15, 1.3, 0.05, 3.1, 0.2), channel(c, 0.12, 1.7, 0.04, 2.9, 1.1),
      channel(0.9, 0.15, 1.1, 0.05, 2.3, 0.4), channel(0.0, 0.25, 1.9, 0.08, 7.1, 0.3),
      channel(0.0, 0.2, 2.3, 0.07, 6.7, 2.0), channel(0.0, 0.2, 2.1, 0.07, 7.9, 1.3)};
  for (int k = 0; k < 6; ++k) {
    const bool keep = motion == RigMotion::kFull || (motion == RigMotion::kPlanar && k != 2 && k != 4 && k != 5);
    if (!keep) channels[static_cast<size_t>(k)].terms.clear();
  }
  const data::SineTrajectory trajectory(start_ns, end_ns, channels);

  data::SimImuOptions io;
  io.gyro_random_walk = 0;  // constant biases: what the calibrator models
  io.accel_random_walk = 0;
  io.initial_gyro_bias = rec.gyro_bias;
  io.initial_accel_bias = rec.accel_bias;
  io.seed = seed;
  io.noise = imu_noise;
  for (const auto& r : data::synthesizeImu(trajectory, io)) {
    rec.imu.t_ns.push_back(r.sample.t_ns);
    rec.imu.gyro.push_back(r.sample.gyro);
    rec.imu.accel.push_back(r.sample.accel);
  }
  rec.imu.rate_hz = io.rate_hz;
  rec.noise = {io.accel_noise_density, 0.003, io.gyro_noise_density, 1.9393e-05, io.rate_hz};

  // Frames stamped t_cam show the pose at t_imu = t_cam + shift.
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, pixel_noise);
  const int64_t shift_ns = static_cast<int64_t>(std::llround(shift_s * 1e9));
  for (int64_t t_cam = start_ns + 250'000'000; t_cam + shift_ns < end_ns - 250'000'000;
       t_cam += 50'000'000) {
    const data::SimBodyState st = trajectory.stateAt(t_cam + shift_ns);
    Eigen::Isometry3d T_T_I = Eigen::Isometry3d::Identity();
    T_T_I.linear() = st.q_W_B.toRotationMatrix();
    T_T_I.translation() = st.p_W_B;
    const Eigen::Isometry3d T_C_T = rec.T_C_I * T_T_I.inverse();
    TargetObservation obs;
    obs.t_ns = t_cam;
    for (int id = 0; id < rec.grid.numTags(); ++id)
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p_T = rec.grid.corner(id, k);
        Eigen::Vector2d uv;
        if (!rec.camera.project(T_C_T * p_T, uv)) continue;
        if (uv.x() < 2 || uv.y() < 2 || uv.x() > rec.camera.width - 3 ||
            uv.y() > rec.camera.height - 3)
          continue;
        uv += Eigen::Vector2d(noise(rng), noise(rng));
        obs.corners.push_back({id, k, uv, p_T});
      }
    rec.views.push_back(obs);
  }
  return rec;
}

}  // namespace adugs::calib::synth

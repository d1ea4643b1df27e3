#pragma once
// Synthetic initialization windows for the initializer tests: a SineTrajectory with real
// excitation (about 0.7 m and 20 deg over 2 s), a forward-looking camera, random points in front of
// it, exact (or noisy) normalised projections and the IMU of data/sim/sim_imu preintegrated between
// the frames.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "data/sim/sim_imu.h"
#include "data/sim/sim_trajectory.h"
#include "vio/init/visual_inertial_initializer.h"

namespace adugs::vio::test {

constexpr int64_t kSceneT0 = 1403715273262142976;  // EuRoC-size epoch

struct InitScene {
  std::vector<InitFrame> frames;
  std::vector<data::SimBodyState> truth;  // per frame
  std::map<int64_t, Eigen::Vector3d> points_W;
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  // true bias at the first frame
};

struct InitSceneOptions {
  int frames = 11;
  double frame_period_s = 0.2;
  double pixel_noise = 0.0;  // std, pixels at focal 460
  bool imu_noise = false;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  double translation_gain = 1.0;  // 0: pure rotation
  double rotation_gain = 1.0;
  bool static_imu = false;  // IMU of a body at rest at the first pose (images still move)
  int points = 200;
  uint64_t seed = 7;
  // The first moving_points of the points move at this constant world velocity (a crowd walking
  // past): the SfM then fits their motion as well as the camera's.
  int moving_points = 0;
  Eigen::Vector3d moving_velocity_W = Eigen::Vector3d::Zero();
};

inline data::SineTrajectory sceneTrajectory(double translation_gain, double rotation_gain) {
  const double a = translation_gain, r = rotation_gain;
  std::array<data::SineChannel, 6> ch;
  ch[data::SineTrajectory::kX] = {0.0, 0.0, {{0.35 * a, 1.6, 0.2}}};
  ch[data::SineTrajectory::kY] = {0.0, 0.0, {{0.4 * a, 2.0, 1.0}}};
  ch[data::SineTrajectory::kZ] = {0.0, 0.0, {{0.15 * a, 2.6, 0.4}}};
  ch[data::SineTrajectory::kYaw] = {0.2, 0.0, {{0.18 * r, 1.3, 0.0}}};
  ch[data::SineTrajectory::kPitch] = {0.0, 0.0, {{0.1 * r, 1.7, 0.5}}};
  ch[data::SineTrajectory::kRoll] = {0.0, 0.0, {{0.12 * r, 2.1, 1.0}}};
  return data::SineTrajectory(kSceneT0, kSceneT0 + data::secToNs(4.0), ch);
}

// Forward-looking camera: z_C = x_B, x_C = -y_B, y_C = -z_B, a few centimetres off the IMU.
inline Eigen::Isometry3d sceneExtrinsic() {
  Eigen::Matrix3d R_B_C;
  R_B_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(0.03, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() * R_B_C;
  T.translation() = Eigen::Vector3d(0.05, -0.02, 0.01);
  return T;
}

inline InitScene makeInitScene(const InitSceneOptions& options = {}) {
  InitScene scene;
  scene.T_B_C = sceneExtrinsic();
  scene.gyro_bias = options.gyro_bias;
  const data::SineTrajectory traj =
      sceneTrajectory(options.translation_gain, options.rotation_gain);

  data::SimImuOptions imu_options;
  imu_options.noise = options.imu_noise;
  imu_options.initial_gyro_bias = options.gyro_bias;
  imu_options.seed = options.seed;
  std::vector<data::SimImuRecord> imu = data::synthesizeImu(traj, imu_options);
  if (options.static_imu) {
    data::SimBodyState rest = traj.stateAt(kSceneT0);
    rest.v_W.setZero();
    rest.a_W.setZero();
    rest.omega_B.setZero();
    for (auto& r : imu) {
      const int64_t t = r.sample.t_ns;
      r.sample = data::idealImu(rest);
      r.sample.t_ns = t;
      r.sample.gyro += options.gyro_bias;
    }
  }

  std::mt19937 rng(static_cast<unsigned>(options.seed));
  std::uniform_real_distribution<double> depth(1.5, 6.0), lateral(-3.0, 3.0), vertical(-2.0, 2.0);
  std::normal_distribution<double> pixel(0.0, options.pixel_noise / 460.0);
  // Points in front of the start pose (body x is forward), fixed in the world.
  const data::SimBodyState start = traj.stateAt(kSceneT0);
  for (int i = 0; i < options.points; ++i) {
    const Eigen::Vector3d p_B0(depth(rng), lateral(rng), vertical(rng));
    scene.points_W[i] = start.q_W_B * p_B0 + start.p_W_B;
  }

  const int64_t period = data::secToNs(options.frame_period_s);
  const int64_t imu_period = data::secToNs(1.0 / imu_options.rate_hz);
  size_t imu_index = 0;
  for (int k = 0; k < options.frames; ++k) {
    InitFrame frame;
    frame.t_ns = kSceneT0 + k * period;
    const data::SimBodyState body = traj.stateAt(frame.t_ns);
    scene.truth.push_back(body);
    const Eigen::Isometry3d T_W_B = Eigen::Translation3d(body.p_W_B) * body.q_W_B;
    const Eigen::Isometry3d T_C_W = (T_W_B * scene.T_B_C).inverse();
    for (const auto& [id, p_W] : scene.points_W) {
      const double moved_s = id < options.moving_points ? data::nsToSec(frame.t_ns - kSceneT0) : 0.0;
      const Eigen::Vector3d p_C = T_C_W * (p_W + moved_s * options.moving_velocity_W);
      if (p_C.z() < 0.5) continue;
      Eigen::Vector2d x = p_C.head<2>() / p_C.z();
      if (std::abs(x.x()) > 0.8 || std::abs(x.y()) > 0.52) continue;  // 752x480 at f = 460
      if (options.pixel_noise > 0) x += Eigen::Vector2d(pixel(rng), pixel(rng));
      frame.ids.push_back(id);
      frame.normalized.push_back(x);
    }
    if (k > 0) {
      // IMU samples are on the frame grid (frame period is a multiple of the IMU period).
      while (imu[imu_index].sample.t_ns < frame.t_ns - period) ++imu_index;
      auto pre = std::make_shared<ImuPreintegration>(imu[imu_index].sample, Eigen::Vector3d::Zero(),
                                                     Eigen::Vector3d::Zero());
      size_t i = imu_index + 1;
      for (; i < imu.size() && imu[i].sample.t_ns <= frame.t_ns; ++i) pre->integrate(imu[i].sample);
      frame.imu_from_previous = pre;
      (void)imu_period;
    }
    scene.frames.push_back(frame);
  }
  return scene;
}

// Ground truth expressed in the initializer's world: origin at the first body, first body yaw
// removed.
struct AlignedTruth {
  std::vector<Eigen::Vector3d> p, v;
  std::vector<Eigen::Quaterniond> q;
  Eigen::Matrix3d R_init_W;  // world -> initializer world
  Eigen::Vector3d p0;        // first body position (world)
};

inline AlignedTruth alignTruth(const std::vector<data::SimBodyState>& truth) {
  AlignedTruth out;
  const Eigen::Matrix3d R0 = truth.front().q_W_B.toRotationMatrix();
  const double yaw0 = std::atan2(R0(1, 0), R0(0, 0));
  out.R_init_W = Eigen::AngleAxisd(-yaw0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out.p0 = truth.front().p_W_B;
  for (const auto& s : truth) {
    out.p.push_back(out.R_init_W * (s.p_W_B - out.p0));
    out.v.push_back(out.R_init_W * s.v_W);
    out.q.push_back(Eigen::Quaterniond(out.R_init_W * s.q_W_B.toRotationMatrix()));
  }
  return out;
}

}  // namespace adugs::vio::test

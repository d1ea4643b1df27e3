// Initialization with the REAL V1_01 IMU (vibration, real biases, real noise) and synthetic
// features projected along the real ground truth: the hybrid setting of the project.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/imu_csv.h"
#include "data/formats/trajectory_io.h"
#include "data/sim/sim_hybrid.h"
#include "tests/test_support.h"
#include "vio/init/visual_inertial_initializer.h"

namespace adugs::vio {
namespace {

using ::adugs::test::kDeg;

std::filesystem::path microDir() { return adugs::test::sharedDataDir() / "euroc_v101_micro"; }

// Preintegration of the real IMU over [from, to], starting and ending at interpolated samples.
std::shared_ptr<ImuPreintegration> preintegrate(const std::vector<data::ImuSample>& imu,
                                                int64_t from, int64_t to) {
  size_t i = 0;
  while (i + 1 < imu.size() && imu[i + 1].t_ns <= from) ++i;
  auto pre = std::make_shared<ImuPreintegration>(interpolateImu(imu[i], imu[i + 1], from),
                                                 Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  for (++i; i < imu.size() && imu[i].t_ns < to; ++i)
    if (imu[i].t_ns > from) pre->integrate(imu[i]);
  pre->integrate(interpolateImu(imu[i - 1], imu[i], to));
  return pre;
}

struct HybridErrors {
  double relative_position = 0, velocity = 0, tilt_deg = 0, gyro_bias = 0;
};

// Initializes on 11 frames 0.2 s apart from t0 + start_s and compares with the ground truth.
HybridErrors runWindow(const std::vector<data::GroundTruthState>& truth,
                       const std::vector<data::ImuSample>& imu, const Eigen::Isometry3d& T_B_C,
                       double start_s, const char* label) {
  // 11 frames, 0.2 s apart (every 4th 20 Hz ground-truth row), from t0 + start_s.
  size_t first = 0;
  while (truth[first].pose.t_ns < truth.front().pose.t_ns + data::secToNs(start_s)) ++first;
  std::vector<data::GroundTruthState> states;
  for (int k = 0; k < 11; ++k) states.push_back(truth[first + 4 * k]);
  auto cameraPose = [&](const data::GroundTruthState& s) {
    return Eigen::Isometry3d(Eigen::Translation3d(s.pose.p_W_B) * s.pose.q_W_B) * T_B_C;
  };
  // Points 1.5 - 6 m in front of the first, middle and last camera (a room-sized scene).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> depth(1.5, 6.0), side(-0.7, 0.7), updown(-0.45, 0.45);
  std::map<int64_t, Eigen::Vector3d> points_W;
  for (int anchor : {0, 5, 10})
    for (int i = 0; i < 120; ++i) {
      const double z = depth(rng);
      points_W[static_cast<int64_t>(points_W.size())] =
          cameraPose(states[anchor]) * Eigen::Vector3d(side(rng) * z, updown(rng) * z, z);
    }
  std::normal_distribution<double> pixel(0.0, 0.5 / 460.0);
  std::vector<InitFrame> frames;
  for (size_t k = 0; k < states.size(); ++k) {
    InitFrame f;
    f.t_ns = states[k].pose.t_ns;
    const Eigen::Isometry3d T_C_W = cameraPose(states[k]).inverse();
    for (const auto& [id, p_W] : points_W) {
      const Eigen::Vector3d p_C = T_C_W * p_W;
      if (p_C.z() < 0.3 || std::abs(p_C.x() / p_C.z()) > 0.8 || std::abs(p_C.y() / p_C.z()) > 0.52)
        continue;
      f.ids.push_back(id);
      f.normalized.push_back(p_C.hnormalized() + Eigen::Vector2d(pixel(rng), pixel(rng)));
    }
    if (k > 0) f.imu_from_previous = preintegrate(imu, states[k - 1].pose.t_ns, f.t_ns);
    frames.push_back(f);
  }

  const InitResult r = initializeVisualInertial(frames, T_B_C);
  EXPECT_TRUE(r.success) << r.failure_reason;
  if (!r.success) return {1e9, 1e9, 1e9, 1e9};
  // Truth in the initializer's world: origin at the first body, its yaw removed.
  const Eigen::Matrix3d R0 = states[0].pose.q_W_B.toRotationMatrix();
  const Eigen::Matrix3d R_init_W =
      Eigen::AngleAxisd(-std::atan2(R0(1, 0), R0(0, 0)), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  double position = 0, extent = 0, velocity = 0, tilt = 0;
  for (size_t k = 0; k < states.size(); ++k) {
    const Eigen::Vector3d p_true = R_init_W * (states[k].pose.p_W_B - states[0].pose.p_W_B);
    position = std::max(position, (r.poses[k].p_W_B - p_true).norm());
    extent = std::max(extent, p_true.norm());
    velocity = std::max(velocity, (r.velocities_W[k] - R_init_W * states[k].v_W).norm());
    const Eigen::Vector3d z_est = r.poses[k].q_W_B.conjugate() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d z_true = states[k].pose.q_W_B.conjugate() * Eigen::Vector3d::UnitZ();
    tilt = std::max(tilt, std::atan2(z_est.cross(z_true).norm(), z_est.dot(z_true)) / kDeg);
  }
  const Eigen::Vector3d bias_error = r.gyro_bias - states[5].gyro_bias;
  std::printf(
      "hybrid V1_01 %s t0+%.0f s: path %.2f m, position %.3f m (%.1f%%), velocity %.3f m/s, "
      "tilt %.2f deg, gyro bias error %.1e rad/s\n",
      label, start_s, extent, position, 100 * position / extent, velocity, tilt, bias_error.norm());
  return {position / extent, velocity, tilt, bias_error.norm()};
}

class VisualInertialInitializerHybrid : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(microDir())) return;
    truth_ = data::readGroundTruthStates(
        (microDir() / "groundtruth" / "V1_01_easy_vicon2gt.csv").string());
    imu_ = data::readEurocImuCsv((microDir() / "mav0" / "imu0" / "data.csv").string());
    T_B_C_ =
        data::readEurocCameraYaml((microDir() / "mav0" / "cam0" / "sensor.yaml").string()).T_B_C;
  }
  std::vector<data::GroundTruthState> truth_;
  std::vector<data::ImuSample> imu_;
  Eigen::Isometry3d T_B_C_ = Eigen::Isometry3d::Identity();
};

TEST_F(VisualInertialInitializerHybrid, RealImuAlongRealFlight) {
  ADUGS_REQUIRE_SHARED(microDir());
  // Measured on these windows: positions 9 - 21% of the path extent, tilt 1.0 - 1.5 deg,
  // velocities <= 0.18 m/s, gyro bias within 2e-3 rad/s of vicon2gt. Most of the position and
  // tilt error is the accelerometer bias, not estimated at initialization (VINS-Mono neither):
  // see the next test.
  for (double start_s : {40.0, 60.0, 100.0}) {
    SCOPED_TRACE(start_s);
    const HybridErrors e = runWindow(truth_, imu_, T_B_C_, start_s, "raw IMU");
    EXPECT_LT(e.relative_position, 0.3);
    EXPECT_LT(e.tilt_deg, 2.0);
    EXPECT_LT(e.velocity, 0.25);
    EXPECT_LT(e.gyro_bias, 3e-3);
  }
}

TEST_F(VisualInertialInitializerHybrid, WithoutTheAccelBiasTheRealImuInitializesAccurately) {
  ADUGS_REQUIRE_SHARED(microDir());
  // The same windows with the vicon2gt accelerometer bias removed from the real samples:
  // measured tilt 0.21 - 0.25 deg, positions 2.3 - 7% (7% on the 0.28 m window at 40 s).
  auto corrected = imu_;
  size_t j = 0;
  for (auto& s : corrected) {
    while (j + 1 < truth_.size() && truth_[j + 1].pose.t_ns <= s.t_ns) ++j;
    s.accel -= truth_[j].accel_bias;
  }
  for (double start_s : {40.0, 60.0, 100.0}) {
    SCOPED_TRACE(start_s);
    const HybridErrors e = runWindow(truth_, corrected, T_B_C_, start_s, "accel bias removed");
    EXPECT_LT(e.relative_position, 0.1);
    EXPECT_LT(e.tilt_deg, 0.5);
    EXPECT_LT(e.velocity, 0.06);
    EXPECT_LT(e.gyro_bias, 3e-3);
  }
}

}  // namespace
}  // namespace adugs::vio

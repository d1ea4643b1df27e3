// The estimator's state carried forward by the IMU (vio/imu/imu_state_predictor.h): hand-worked
// constant-acceleration and constant-rate cases, the camera's displacement between two states, and
// on the real EuRoC V1_01 IMU and ground truth what the motion cue gains over a velocity three
// frames old.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/imu_csv.h"
#include "data/formats/trajectory_io.h"
#include "tests/test_support.h"
#include "vio/imu/imu_dead_reckoning.h"  // interpolateGroundTruth
#include "vio/imu/imu_state_predictor.h"

namespace adugs::vio {
// Named, not anonymous: the sanitizer stage's unity build puts several test files in one unit.
namespace imu_state_predictor_test {

// 200 Hz over 0.2 s of a level body: specific force f_B (gravity's reaction included), rate omega.
ImuStatePredictor constantImu(const Eigen::Vector3d& f_B, const Eigen::Vector3d& omega) {
  ImuStatePredictor p;
  for (int k = 0; k <= 40; ++k) {
    data::ImuSample s;
    s.t_ns = 5'000'000LL * k;
    s.accel = f_B;
    s.gyro = omega;
    p.addImu(s);
  }
  return p;
}

TEST(ImuStatePredictor, CarriesAConstantAccelerationExactlyBetweenOffGridTimes) {
  // Level body, world acceleration a = (0.4, -0.2, 0): the accelerometer reads a - g plus its bias.
  const Eigen::Vector3d a(0.4, -0.2, 0), bias(0.05, 0, -0.02);
  const ImuStatePredictor p = constantImu(a - gravityWorld() + bias, Eigen::Vector3d::Zero());
  NavState from;
  from.t_ns = 12'300'000;  // between samples
  from.p_W_B = Eigen::Vector3d(1, 2, 3);
  from.v_W = Eigen::Vector3d(0.5, 0, -0.1);
  from.accel_bias = bias;
  const NavState to = p.predict(from, 61'700'000);
  const double dt = 0.0494;
  EXPECT_EQ(to.t_ns, 61'700'000);
  EXPECT_LT((to.p_W_B - (from.p_W_B + from.v_W * dt + 0.5 * a * dt * dt)).norm(), 1e-12);
  EXPECT_LT((to.v_W - (from.v_W + a * dt)).norm(), 1e-12);
  // Past the last sample (0.2 s) the last reading is held: still exact.
  const NavState late = p.predict(from, 250'000'000);
  const double dt_late = 0.2377;
  EXPECT_LT((late.v_W - (from.v_W + a * dt_late)).norm(), 1e-12);
  // Nothing to carry: the state itself.
  EXPECT_EQ(p.predict(from, from.t_ns).p_W_B, from.p_W_B);
  EXPECT_EQ(ImuStatePredictor().predict(from, 61'700'000).t_ns, from.t_ns);
}

TEST(ImuStatePredictor, TurnsWithTheGyroLessItsBias) {
  // Yawing at 0.5 rad/s (the gyro reads 0.53 with a 0.03 bias), moving at 1 m/s along world x,
  // no acceleration: the attitude turns by 0.5 * 0.1 rad, the velocity stays.
  const Eigen::Vector3d bias(0, 0, 0.03);
  const ImuStatePredictor p = constantImu(-gravityWorld(), Eigen::Vector3d(0, 0, 0.5) + bias);
  NavState from;
  from.t_ns = 50'000'000;
  from.v_W = Eigen::Vector3d(1, 0, 0);
  from.gyro_bias = bias;
  const NavState to = p.predict(from, 150'000'000);
  EXPECT_LT(to.q_W_B.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()))), 1e-12);
  EXPECT_LT((to.v_W - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((to.p_W_B - Eigen::Vector3d(0.1, 0, 0)).norm(), 1e-12);
}

TEST(ImuStatePredictor, RefusesSamplesOutOfOrder) {
  ImuStatePredictor p;
  data::ImuSample s;
  s.t_ns = 10;
  p.addImu(s);
  EXPECT_THROW(p.addImu(s), std::invalid_argument);
  p.dropBefore(1000);
  EXPECT_EQ(p.size(), 1u) << "the last sample before a time is kept: it interpolates the reading there";
}

TEST(CameraDisplacement, HandWorkedLeverArmAndMount) {
  // The body moves 1 m along world x and turns 90 degrees about z; the camera sits 0.1 m ahead of
  // the body along its x, turned +90 degrees about the body's x. Camera centre: (0.1, 0, 0) ->
  // (1, 0.1, 0), so (0.9, 0.1, 0) in the world, (0.1, -0.9, 0) in the turned body, and
  // Rx(90)^T (0.1, -0.9, 0) = (0.1, 0, 0.9) in the camera.
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();
  T_B_C.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T_B_C.translation() = Eigen::Vector3d(0.1, 0, 0);
  NavState before, after;
  after.p_W_B = Eigen::Vector3d(1, 0, 0);
  after.q_W_B = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  EXPECT_LT((cameraDisplacement(before, after, T_B_C) - Eigen::Vector3d(0.1, 0, 0.9)).norm(), 1e-12);
}

// Angle between two displacements, degrees.
double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(ImuStatePredictor, GivesTheMotionCueTheDirectionOfTravelOnEurocV101) {
  // The motion cue at frame k gets the estimator's state after frame k - 3 and needs the camera's
  // displacement from frame k - 1 to k. Here the state is the ground truth's (pose, velocity,
  // biases) and the IMU the real one, over the whole V1_01 flight at the camera's 20 Hz: carried
  // by the IMU, the direction is close to the truth; the velocity three frames old, as the cue
  // used it before, is not when the drone turns.
  const auto euroc = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(euroc / "groundtruth/V1_01_easy_vicon2gt.csv");
  const std::vector<data::GroundTruthState> gt =
      data::readGroundTruthStates((euroc / "groundtruth/V1_01_easy_vicon2gt.csv").string());
  const Eigen::Isometry3d T_B_C = data::readEurocCameraYaml((euroc / "mav0/cam0/sensor.yaml").string()).T_B_C;
  ImuStatePredictor imu;
  for (const data::ImuSample& s : data::readEurocImuCsv((euroc / "mav0/imu0/data.csv").string())) imu.addImu(s);
  const int64_t frame_ns = 50'000'000;
  std::vector<double> carried, held, length_error;
  for (int64_t t = gt.front().pose.t_ns + 3 * frame_ns; t <= gt.back().pose.t_ns; t += frame_ns) {
    const auto start = interpolateGroundTruth(gt, t - 3 * frame_ns), previous = interpolateGroundTruth(gt, t - frame_ns),
               now = interpolateGroundTruth(gt, t);
    ASSERT_TRUE(start && previous && now);
    const Eigen::Vector3d truth = cameraDisplacement(*previous, *now, T_B_C);
    if (truth.norm() < 0.01) continue;  // under 0.2 m/s: the cue takes it for no translation
    const Eigen::Vector3d predicted = cameraDisplacement(imu.predict(*start, t - frame_ns), imu.predict(*start, t), T_B_C);
    const Eigen::Vector3d old =
        T_B_C.rotation().transpose() * (start->q_W_B.conjugate() * start->v_W) * (frame_ns * 1e-9);
    carried.push_back(angleDeg(predicted, truth));
    held.push_back(angleDeg(old, truth));
    length_error.push_back(std::abs(predicted.norm() - truth.norm()) / truth.norm());
  }
  ASSERT_GT(carried.size(), 2000u);
  std::sort(carried.begin(), carried.end());
  std::sort(held.begin(), held.end());
  const auto p90 = [](const std::vector<double>& v) { return v[v.size() * 9 / 10]; };
  RecordProperty("median_deg", std::to_string(median(carried)) + " against " + std::to_string(median(held)));
  std::printf("direction error, median / 90th percentile [deg]: carried %.2f / %.2f, held %.2f / %.2f; length %.3f\n",
              median(carried), p90(carried), median(held), p90(held), median(length_error));
  EXPECT_LT(median(carried), 1.0);
  EXPECT_LT(p90(carried), 3.0);
  EXPECT_LT(median(length_error), 0.03);
  EXPECT_LT(p90(carried), p90(held) / 2) << "carrying the state must beat the velocity three frames old";
}

}  // namespace imu_state_predictor_test
}  // namespace adugs::vio

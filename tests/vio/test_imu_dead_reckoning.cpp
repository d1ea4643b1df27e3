#include <gtest/gtest.h>

#include "vio/imu/imu_dead_reckoning.h"

namespace adugs::vio {
namespace {

data::GroundTruthState gtState(int64_t t_ns, const Eigen::Vector3d& p, double yaw) {
  data::GroundTruthState s;
  s.pose.t_ns = t_ns;
  s.pose.p_W_B = p;
  s.pose.q_W_B = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  s.has_velocity_and_biases = true;
  s.v_W = Eigen::Vector3d(1, 0, 0);
  s.accel_bias = Eigen::Vector3d(0.1, 0, 0) * static_cast<double>(t_ns) * 1e-9;
  return s;
}

TEST(InterpolateGroundTruth, HandWorkedMidpointAndRange) {
  std::vector<data::GroundTruthState> gt = {gtState(1'000'000'000, {0, 0, 0}, 0.0),
                                            gtState(2'000'000'000, {2, 4, 0}, 0.5)};
  const auto s = interpolateGroundTruth(gt, 1'250'000'000);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->p_W_B.isApprox(Eigen::Vector3d(0.5, 1.0, 0)));
  EXPECT_NEAR(Eigen::AngleAxisd(s->q_W_B).angle(), 0.125, 1e-12);
  EXPECT_NEAR(s->accel_bias.x(), 0.125, 1e-12);
  EXPECT_FALSE(interpolateGroundTruth(gt, 999'999'999));
  EXPECT_FALSE(interpolateGroundTruth(gt, 2'000'000'001));
  EXPECT_TRUE(interpolateGroundTruth(gt, 2'000'000'000));
}

TEST(ImuDeadReckoning, FollowsConstantVelocityFromTheGroundTruthStart) {
  std::vector<data::GroundTruthState> gt = {gtState(0, {0, 0, 0}, 0.0),
                                            gtState(10'000'000'000, {10, 0, 0}, 0.0)};
  for (auto& s : gt) s.accel_bias.setZero();
  ImuDeadReckoning dr(gt);
  EXPECT_FALSE(dr.poseAt(0));
  for (int k = 0; k <= 400; ++k) {  // 2 s at 200 Hz, level, no acceleration
    data::ImuSample imu;
    imu.t_ns = k * 5'000'000LL;
    imu.accel = Eigen::Vector3d(0, 0, 9.81);
    dr.addImu(imu);
  }
  const auto pose = dr.poseAt(2'010'000'000);  // 10 ms after the last sample (held reading)
  ASSERT_TRUE(pose);
  EXPECT_TRUE(pose->p_W_B.isApprox(Eigen::Vector3d(2.01, 0, 0), 1e-9));
  EXPECT_FALSE(dr.poseAt(1'000'000'000)) << "no poses before the last integrated sample";
}

}  // namespace
}  // namespace adugs::vio

// ImuUnifier (accelerometer interpolated onto gyro stamps) and StampReorderBuffer, on hand-worked
// cases.
#include <gtest/gtest.h>

#include "data/sources/imu_unifier.h"
#include "data/sources/stamp_reorder_buffer.h"

namespace adugs::data {
namespace {

TEST(ImuUnifier, InterpolatesTheAccelerometerAtGyroStamps) {
  ImuUnifier u;
  ImuSample s;
  u.addGyro(500, {9, 9, 9});  // before any accelerometer sample: dropped once one arrives
  u.addAccel(1000, {0, 0, 0});
  u.addGyro(1000, {1, 0, 0});  // same stamp as the accelerometer: taken as is
  u.addGyro(2000, {2, 0, 0});  // waits for the next accelerometer sample
  ASSERT_TRUE(u.pop(&s));
  EXPECT_EQ(s.t_ns, 1000);
  EXPECT_EQ(s.gyro, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.accel, Eigen::Vector3d(0, 0, 0));
  EXPECT_FALSE(u.pop(&s));
  EXPECT_EQ(u.unmatched(), 1u);

  u.addAccel(5000, {4, 8, -4});
  // t = 2000 lies a quarter of the way from 1000 to 5000: accel = 0.75 * 0 + 0.25 * (4, 8, -4).
  ASSERT_TRUE(u.pop(&s));
  EXPECT_EQ(s.t_ns, 2000);
  EXPECT_EQ(s.gyro, Eigen::Vector3d(2, 0, 0));
  EXPECT_TRUE(s.accel.isApprox(Eigen::Vector3d(1, 2, -1)));

  u.addGyro(4000, {3, 0, 0});  // three quarters: (3, 6, -3)
  ASSERT_TRUE(u.pop(&s));
  EXPECT_TRUE(s.accel.isApprox(Eigen::Vector3d(3, 6, -3)));
  u.addGyro(6000, {4, 0, 0});  // after the last accelerometer sample
  EXPECT_FALSE(u.pop(&s));
  EXPECT_EQ(u.pendingGyro(), 1u);
  u.finish();
  EXPECT_EQ(u.unmatched(), 2u);
  EXPECT_EQ(u.pendingGyro(), 0u);
}

TEST(ImuUnifier, UsesTheTwoAccelerometerSamplesAroundEachGyroStamp) {
  ImuUnifier u;
  for (int k = 0; k <= 10; ++k) u.addAccel(k * 4000, Eigen::Vector3d(k * 4.0, 0, 0));  // a = t / 1000
  ImuSample s;
  for (int64_t t = 0; t <= 40000; t += 2500) {
    u.addGyro(t, Eigen::Vector3d::Zero());
    ASSERT_TRUE(u.pop(&s)) << t;
    EXPECT_NEAR(s.accel.x(), t / 1000.0, 1e-12) << t;
  }
  EXPECT_EQ(u.unmatched(), 0u);
}

TEST(StampReorderBuffer, ReleasesInStampOrderOnceTheWindowHasPassed) {
  StampReorderBuffer<int> b(10);
  int v = 0;
  int64_t t = 0;
  EXPECT_TRUE(b.push(100, 1, 1));  // an image recorded late ...
  EXPECT_TRUE(b.push(95, 0, 2));   // ... after IMU stamped before it
  EXPECT_TRUE(b.push(100, 0, 3));  // IMU at the image's stamp: rank 0 goes first
  EXPECT_FALSE(b.pop(&v, &t));     // newest 100 - oldest 95 <= 10: still inside the window
  EXPECT_TRUE(b.push(106, 0, 4));
  ASSERT_TRUE(b.pop(&v, &t));  // 106 - 95 > 10
  EXPECT_EQ(v, 2);
  EXPECT_EQ(t, 95);
  EXPECT_FALSE(b.pop(&v, &t));  // 106 - 100 <= 10
  EXPECT_FALSE(b.push(90, 0, 5));  // older than what was released: too late, refused
  ASSERT_TRUE(b.pop(&v, &t, true));
  EXPECT_EQ(v, 3);
  ASSERT_TRUE(b.pop(&v, &t, true));
  EXPECT_EQ(v, 1);
  ASSERT_TRUE(b.pop(&v, &t, true));
  EXPECT_EQ(v, 4);
  EXPECT_FALSE(b.pop(&v, &t, true));
}

}  // namespace
}  // namespace adugs::data

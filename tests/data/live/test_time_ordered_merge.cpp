// TimeOrderedMerge on hand-worked arrivals: release order, latency bounds, late and out-of-order
// refusals, flushing.
#include <gtest/gtest.h>

#include "data/sources/time_ordered_merge.h"

namespace adugs::data {
namespace {

data::Measurement imu(int64_t t) {
  data::Measurement m;
  m.type = data::Measurement::Type::kImu;
  m.imu.t_ns = t;
  return m;
}
data::Measurement frame(int64_t t) {
  data::Measurement m;
  m.type = data::Measurement::Type::kFrame;
  m.frame.t_ns = t;
  return m;
}

TEST(TimeOrderedMerge, WaitsForEveryStreamToPassAStampOrItsLatencyBound) {
  data::TimeOrderedMerge merge;
  const int frames = merge.addStream(0.2), samples = merge.addStream(0.1);  // 200 ms, 100 ms
  data::Measurement m;
  EXPECT_FALSE(merge.pop(0, &m));
  EXPECT_EQ(merge.releaseDeadlineNs(), INT64_MAX);
  ASSERT_TRUE(merge.push(samples, imu(1'000'000'000)));
  ASSERT_TRUE(merge.push(samples, imu(1'002'500'000)));
  // No frame yet: the IMU waits until a frame stamped after it could no longer come (200 ms).
  EXPECT_FALSE(merge.pop(1'010'000'000, &m));
  EXPECT_EQ(merge.releaseDeadlineNs(), 1'200'000'000);
  // A frame stamped 1.001 s (it arrived late, after its exposure): it goes between the two.
  ASSERT_TRUE(merge.push(frames, frame(1'001'000'000)));
  ASSERT_TRUE(merge.pop(1'010'000'000, &m));
  EXPECT_EQ(m.timeNs(), 1'000'000'000);
  EXPECT_TRUE(m.isImu());
  ASSERT_TRUE(merge.pop(1'010'000'000, &m));
  EXPECT_TRUE(m.isFrame());
  // 1.0025 s: the frame stream passed 1.001 only; released after 1.0025 + 0.2 s of silence.
  EXPECT_FALSE(merge.pop(1'100'000'000, &m));
  ASSERT_TRUE(merge.pop(1'202'500'000, &m));
  EXPECT_EQ(m.timeNs(), 1'002'500'000);
  // Late now: a frame stamped before what was released; an IMU sample not after the previous one.
  EXPECT_FALSE(merge.push(frames, frame(1'002'000'000)));
  EXPECT_EQ(merge.late(frames), 1u);
  EXPECT_FALSE(merge.push(samples, imu(1'002'500'000)));
  EXPECT_EQ(merge.outOfOrder(samples), 1u);
}

TEST(TimeOrderedMerge, ImuFirstOnEqualStampsAndFlush) {
  data::TimeOrderedMerge merge;
  const int frames = merge.addStream(0.05), samples = merge.addStream(0.05), other = merge.addStream(0.05);
  ASSERT_TRUE(merge.push(other, imu(100)));
  ASSERT_TRUE(merge.push(frames, frame(500)));
  ASSERT_TRUE(merge.push(samples, imu(500)));
  ASSERT_TRUE(merge.push(samples, imu(700)));
  data::Measurement m;
  ASSERT_TRUE(merge.pop(0, &m));
  EXPECT_EQ(m.timeNs(), 100);
  EXPECT_FALSE(merge.pop(0, &m));  // `other` has not passed 500 yet
  ASSERT_TRUE(merge.pop(100'000'000, &m));  // ... nor spoken for 0.1 s
  EXPECT_TRUE(m.isImu());  // same stamp: IMU first
  ASSERT_TRUE(merge.pop(100'000'000, &m));
  EXPECT_TRUE(m.isFrame());
  EXPECT_FALSE(merge.pop(0, &m));  // 700: the frame stream has not passed it
  EXPECT_FALSE(merge.push(other, imu(500)));  // an IMU sample after the frame of its stamp went out
  EXPECT_EQ(merge.late(other), 1u);
  ASSERT_TRUE(merge.pop(0, &m, true));  // flush: the streams ended
  EXPECT_EQ(m.timeNs(), 700);
  EXPECT_TRUE(merge.empty());
}

}  // namespace
}  // namespace adugs::data

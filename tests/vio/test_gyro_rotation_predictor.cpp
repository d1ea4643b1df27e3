// The front-end's gyro-only rotation prediction (vio/imu/gyro_rotation_predictor.h).
#include <gtest/gtest.h>

#include "vio/imu/gyro_rotation_predictor.h"

namespace adugs::vio {
namespace {

// A rate growing linearly about a fixed axis, omega(t) = (a + b t) axis, plus a constant bias:
// the rotation angle over [t0, t1] is a (t1 - t0) + b (t1^2 - t0^2) / 2, which the midpoint rule
// with linearly interpolated end rates integrates exactly.
GyroRotationPredictor linearRamp(const Eigen::Vector3d& axis, double a, double b,
                                 const Eigen::Vector3d& bias) {
  GyroRotationPredictor p;
  for (int k = 0; k <= 40; ++k) {  // 200 Hz over 0.2 s
    data::ImuSample s;
    s.t_ns = 5'000'000LL * k;
    const double t = data::nsToSec(s.t_ns);
    s.gyro = (a + b * t) * axis + bias;
    p.addImu(s);
  }
  return p;
}

TEST(GyroRotationPredictor, IntegratesALinearRampExactlyBetweenOffGridTimes) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  const Eigen::Vector3d bias(0.02, -0.01, 0.03);
  const double a = 0.8, b = 6.0;
  const GyroRotationPredictor p = linearRamp(axis, a, b, bias);
  const int64_t t0 = 12'300'000, t1 = 61'700'000;  // 12.3 ms .. 61.7 ms, between samples
  const double s0 = data::nsToSec(t0), s1 = data::nsToSec(t1);
  const double angle = a * (s1 - s0) + 0.5 * b * (s1 * s1 - s0 * s0);  // 0.0395 + 0.01096
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
  const Eigen::Quaterniond q = p.rotation(t0, t1, bias);
  EXPECT_LT(q.angularDistance(expected), 1e-12);
  // Ignoring the bias rotates by bias * 49.4 ms more.
  const Eigen::Quaterniond biased = p.rotation(t0, t1, Eigen::Vector3d::Zero());
  EXPECT_NEAR(biased.angularDistance(expected), (s1 - s0) * bias.norm(), 1e-4);
}

TEST(GyroRotationPredictor, IdentityWithoutSamplesOrForAnEmptyInterval) {
  GyroRotationPredictor empty;
  EXPECT_LT(empty.rotation(0, 50'000'000, Eigen::Vector3d::Zero())
                .angularDistance(Eigen::Quaterniond::Identity()),
            1e-15);
  const GyroRotationPredictor p = linearRamp(Eigen::Vector3d::UnitZ(), 1.0, 0.0, {0, 0, 0});
  EXPECT_LT(p.rotation(50'000'000, 50'000'000, Eigen::Vector3d::Zero())
                .angularDistance(Eigen::Quaterniond::Identity()),
            1e-15);
  EXPECT_LT(p.rotation(60'000'000, 50'000'000, Eigen::Vector3d::Zero())
                .angularDistance(Eigen::Quaterniond::Identity()),
            1e-15);
}

TEST(GyroRotationPredictor, DroppingOldSamplesKeepsLaterIntervalsUnchanged) {
  GyroRotationPredictor p = linearRamp(Eigen::Vector3d::UnitY(), 0.3, 4.0, {0.01, 0, 0});
  const Eigen::Quaterniond before = p.rotation(102'000'000, 148'000'000, {0.01, 0, 0});
  const size_t n = p.size();
  p.dropBefore(102'000'000);
  EXPECT_LT(p.size(), n);
  EXPECT_LT(p.rotation(102'000'000, 148'000'000, {0.01, 0, 0}).angularDistance(before), 1e-15);
}

// Past the newest sample the rate is held: 0.1 s beyond a constant 1 rad/s is 0.1 rad.
TEST(GyroRotationPredictor, HoldsTheNewestRateBeyondTheBuffer) {
  const GyroRotationPredictor p = linearRamp(Eigen::Vector3d::UnitX(), 1.0, 0.0, {0, 0, 0});
  const Eigen::Quaterniond q = p.rotation(200'000'000, 300'000'000, Eigen::Vector3d::Zero());
  EXPECT_NEAR(Eigen::AngleAxisd(q).angle(), 0.1, 1e-12);
}

}  // namespace
}  // namespace adugs::vio

#include <gtest/gtest.h>

#include <cmath>

#include "tests/vio/jacobian_check.h"
#include "vio/estimator/bias_prior_factor.h"
#include "vio/estimator/landmark_map.h"
#include "vio/estimator/scalar_prior_factor.h"
#include "vio/estimator/zero_velocity_factor.h"

namespace adugs::vio {
namespace {

Eigen::Isometry3d cameraAt(double x, double y, double z) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

FrameFeatures featuresOf(int64_t t, const std::vector<int64_t>& ids,
                         const std::vector<Eigen::Vector2d>& pts) {
  FrameFeatures f;
  f.t_ns = t;
  f.ids = ids;
  f.normalized = pts;
  f.velocities.assign(ids.size(), Eigen::Vector2d::Zero());
  f.track_counts.assign(ids.size(), 1);
  return f;
}

// Point (1, 0.5, 4) seen from x = 0 and x = 1 (cameras looking along +z):
// normalised (0.25, 0.125) and (0, 0.125); depth 4 in the host.
TEST(LandmarkMap, TriangulatesAHandWorkedPoint) {
  const std::vector<Eigen::Isometry3d> T_W_C{cameraAt(0, 0, 0), cameraAt(1, 0, 0)};
  Eigen::Vector3d p;
  ASSERT_TRUE(triangulatePoint({{0.25, 0.125}, {0.0, 0.125}}, T_W_C, &p));
  EXPECT_LT((p - Eigen::Vector3d(1, 0.5, 4)).norm(), 1e-12);

  LandmarkMap map;
  map.addFrame(0, featuresOf(1, {7}, {{0.25, 0.125}}));
  map.addFrame(1, featuresOf(2, {7}, {{0.0, 0.125}}));
  EXPECT_EQ(map.triangulate(T_W_C), 1);
  EXPECT_NEAR(map.landmarks().at(7).inverse_depth, 0.25, 1e-12);
  EXPECT_LT((map.worldPoint(map.landmarks().at(7), T_W_C) - Eigen::Vector3d(1, 0.5, 4)).norm(),
            1e-12);
}

TEST(LandmarkMap, RefusesPointsWithoutParallaxOrBehindTheCamera) {
  LandmarkMap map;
  // Same camera twice: no baseline.
  map.addFrame(0, featuresOf(1, {1}, {{0.1, 0.1}}));
  map.addFrame(1, featuresOf(2, {1}, {{0.1, 0.1}}));
  EXPECT_EQ(map.triangulate({cameraAt(0, 0, 0), cameraAt(0, 0, 0)}), 0);
  // Rays meeting behind the cameras: (-0.25 from x=0, 0 from x=1) -> x = 1 at depth -4.
  LandmarkMap behind;
  behind.addFrame(0, featuresOf(1, {2}, {{-0.25, 0.0}}));
  behind.addFrame(1, featuresOf(2, {2}, {{0.0, 0.0}}));
  EXPECT_EQ(behind.triangulate({cameraAt(0, 0, 0), cameraAt(1, 0, 0)}), 0);
  // 1 cm baseline at 4 m: 0.14 degrees, below the 1 degree default.
  LandmarkMap far;
  far.addFrame(0, featuresOf(1, {3}, {{0.0, 0.0}}));
  far.addFrame(1, featuresOf(2, {3}, {{-0.0025, 0.0}}));
  EXPECT_EQ(far.triangulate({cameraAt(0, 0, 0), cameraAt(0.01, 0, 0)}), 0);
  EXPECT_EQ(far.triangulate({cameraAt(0, 0, 0), cameraAt(0.01, 0, 0)}, 0.1, 80.0, 0.0), 1);
}

TEST(LandmarkMap, ParallaxAndFrameRemovalCarryTheDepthToTheNewHost) {
  const std::vector<Eigen::Isometry3d> T_W_C{cameraAt(0, 0, 0), cameraAt(1, 0, 0),
                                             cameraAt(2, 0, 0)};
  LandmarkMap map;
  // Point (1, 0.5, 4): normalised x = (1 - cx) / 4.
  map.addFrame(0, featuresOf(1, {5, 6}, {{0.25, 0.125}, {0.0, 0.0}}));
  map.addFrame(1, featuresOf(2, {5, 6}, {{0.0, 0.125}, {0.03, 0.04}}));
  map.addFrame(2, featuresOf(3, {5}, {{-0.25, 0.125}}));
  int common = 0;
  // Frames 0 and 1: displacements 0.25 and 0.05 -> mean 0.15 over 2 features.
  EXPECT_NEAR(map.meanParallax(0, 1, &common), 0.15, 1e-12);
  EXPECT_EQ(common, 2);
  map.setWorldPoint(5, Eigen::Vector3d(1, 0.5, 4), T_W_C);
  ASSERT_TRUE(map.landmarks().at(5).has_depth);
  map.removeFrame(0, &T_W_C);
  const Landmark& l = map.landmarks().at(5);
  EXPECT_EQ(l.hostFrame(), 0);  // the old frame 1, shifted down
  ASSERT_EQ(l.observations.size(), 2u);
  EXPECT_EQ(l.observations[1].frame, 1);
  ASSERT_TRUE(l.has_depth);
  EXPECT_NEAR(l.inverse_depth, 0.25, 1e-12);  // still 4 m deep from the camera at x = 1
  // Without poses the depth is dropped; a landmark left without observations disappears.
  map.removeFrame(0, nullptr);
  EXPECT_FALSE(map.landmarks().at(5).has_depth);
  EXPECT_EQ(map.landmarks().count(6), 0u);
}

// A rejected landmark is gone and its id is ignored while the tracker keeps reporting it; once a
// frame comes without it the map forgets the id (ids are never reused, so the set stays small).
TEST(LandmarkMap, RejectedIdsStayOutWhileTracked) {
  LandmarkMap map;
  map.addFrame(0, featuresOf(1, {1, 2}, {{0.1, 0.1}, {0.2, 0.2}}));
  map.addFrame(1, featuresOf(2, {1, 2}, {{0.1, 0.1}, {0.2, 0.2}}));
  map.reject(2);
  EXPECT_EQ(map.size(), 1);
  EXPECT_TRUE(map.isRejected(2));
  map.addFrame(2, featuresOf(3, {1, 2}, {{0.1, 0.1}, {0.2, 0.2}}));
  EXPECT_EQ(map.landmarks().count(2), 0u) << "a rejected id came back while still tracked";
  EXPECT_EQ(map.landmarks().at(1).observations.size(), 3u);
  map.addFrame(3, featuresOf(4, {1}, {{0.1, 0.1}}));
  EXPECT_FALSE(map.isRejected(2)) << "the id left the tracker; the set should forget it";
  map.reject(1);
  map.clear();
  EXPECT_FALSE(map.isRejected(1)) << "a reset starts with no rejected ids";
}

TEST(ZeroVelocityFactor, ResidualAndJacobian) {
  ZeroVelocityFactor f(0.01);
  double sb[9] = {0.02, -0.01, 0.005, 0.1, 0.2, 0.3, 0.01, 0.02, 0.03};
  const double* params[] = {sb};
  double r[3];
  ASSERT_TRUE(f.Evaluate(params, r, nullptr));
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_NEAR(r[1], -1.0, 1e-12);
  EXPECT_NEAR(r[2], 0.5, 1e-12);
  const auto check = testing::checkJacobians(f, {sb}, {nullptr});
  EXPECT_TRUE(check.ok) << check.report;
}

TEST(BiasPriorFactor, GyroResidualAndJacobian) {
  BiasPriorFactor f(BiasPriorFactor::Bias::kGyro, Eigen::Vector3d(0.002, 0.021, 0.078),
                    Eigen::Vector3d(0.001, 0.002, 0.004));
  double sb[9] = {0.02, -0.01, 0.005, 0.1, 0.2, 0.3, 0.004, 0.017, 0.078};
  const double* params[] = {sb};
  double r[3];
  ASSERT_TRUE(f.Evaluate(params, r, nullptr));
  EXPECT_NEAR(r[0], 2.0, 1e-12);   // (0.004 - 0.002) / 0.001
  EXPECT_NEAR(r[1], -2.0, 1e-12);  // (0.017 - 0.021) / 0.002
  EXPECT_NEAR(r[2], 0.0, 1e-12);
  const auto check = testing::checkJacobians(f, {sb}, {nullptr});
  EXPECT_TRUE(check.ok) << check.report;
}

// Hand-worked: x rates 0.01 and 0.03 rad/s (mean 0.02, sample std 0.0141421) against a white
// noise of 1e-4 * sqrt(200) = 0.00141421 per sample; y and z constant (the white noise wins).
TEST(BiasPriorFactor, AccelResidualAndJacobian) {
  BiasPriorFactor f(BiasPriorFactor::Bias::kAccel, Eigen::Vector3d(0.1, -0.2, 0.05), Eigen::Vector3d(0.05, 0.05, 0.1));
  double sb[9] = {0.02, -0.01, 0.005, 0.2, -0.2, 0.0, 0.004, 0.017, 0.078};
  const double* params[] = {sb};
  double r[3];
  ASSERT_TRUE(f.Evaluate(params, r, nullptr));
  EXPECT_NEAR(r[0], 2.0, 1e-12);   // (0.2 - 0.1) / 0.05
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[2], -0.5, 1e-12);  // (0 - 0.05) / 0.1
  const auto check = testing::checkJacobians(f, {sb}, {nullptr});
  EXPECT_TRUE(check.ok) << check.report;
}

TEST(GyroAtRest, MeanAndStandardErrorOfTheRatesAtRest) {
  Eigen::Vector3d mean, sigma;
  ASSERT_TRUE(gyroMeanAtRest({Eigen::Vector3d(0.01, 0.5, -0.2), Eigen::Vector3d(0.03, 0.5, -0.2)}, 200.0, 1e-4,
                             &mean, &sigma));
  EXPECT_NEAR(mean.x(), 0.02, 1e-15);
  EXPECT_NEAR(mean.y(), 0.5, 1e-15);
  EXPECT_NEAR(sigma.x(), 0.0141421356 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(sigma.y(), 1e-4 * std::sqrt(200.0) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(sigma.z(), sigma.y(), 1e-15);
  EXPECT_FALSE(gyroMeanAtRest({Eigen::Vector3d::Zero()}, 200.0, 1e-4, &mean, &sigma)) << "one sample has no spread";
}

TEST(ScalarPriorFactor, ResidualAndJacobian) {
  ScalarPriorFactor f(0.004, 0.002);  // calibrated td 4 ms, sigma 2 ms
  double td = 0.001;
  const double* params[] = {&td};
  double r;
  ASSERT_TRUE(f.Evaluate(params, &r, nullptr));
  EXPECT_NEAR(r, -1.5, 1e-12);  // (1 - 4) / 2
  const auto check = testing::checkJacobians(f, {&td}, {nullptr});
  EXPECT_TRUE(check.ok) << check.report;
}

}  // namespace
}  // namespace adugs::vio

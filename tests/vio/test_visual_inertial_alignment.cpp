// Visual-inertial alignment: the linear system by hand, then each solve against exact windows.
#include <gtest/gtest.h>

#include <cmath>

#include "init_test_scene.h"
#include "vio/init/visual_inertial_alignment.h"

namespace adugs::vio {
namespace {

// Constant specific force f and zero rate for dt seconds (midpoint integration is then exact:
// delta_p = f dt^2 / 2, delta_v = f dt).
std::shared_ptr<ImuPreintegration> constantForce(const Eigen::Vector3d& f, double dt) {
  data::ImuSample s;
  s.accel = f;
  auto pre =
      std::make_shared<ImuPreintegration>(s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  for (int i = 1; i <= 10; ++i) {
    s.t_ns = data::secToNs(0.1 * i * dt);
    pre->integrate(s);
  }
  return pre;
}

TEST(VisualInertialAlignment, TwoFrameSystemByHand) {
  // World = c0, no rotation, gravity (0, 0, -9.81). The body starts with v0 = (1, 0, 0) and
  // accelerates at a = (0.2, 0, 0) for 1 s: p1 = (1.1, 0, 0), v1 = (1.2, 0, 0). The IMU measures
  // f = a - g = (0.2, 0, 9.81): alpha = (0.1, 0, 4.905), beta = (0.2, 0, 9.81).
  // The camera sits 0.1 m along body y; the SfM has scale s = 2 (metric = 2 x SfM), so the SfM
  // camera positions are (0, 0.1, 0) / 2 and (1.1, 0.1, 0) / 2.
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();
  T_B_C.translation() = Eigen::Vector3d(0, 0.1, 0);
  std::vector<AlignmentFrame> frames(2);
  frames[0].p_c0_c = Eigen::Vector3d(0, 0.05, 0);
  frames[1].p_c0_c = Eigen::Vector3d(0.55, 0.05, 0);
  frames[1].imu_from_previous = constantForce(Eigen::Vector3d(0.2, 0, 9.81), 1.0);
  EXPECT_LT((frames[1].imu_from_previous->deltaP() - Eigen::Vector3d(0.1, 0, 4.905)).norm(), 1e-12);

  LinearAlignment truth;
  truth.velocities_body = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1.2, 0, 0)};
  truth.gravity_c0 = Eigen::Vector3d(0, 0, -9.81);
  truth.scale = 2.0;
  const Eigen::VectorXd r = alignmentResidual(frames, T_B_C, truth);
  ASSERT_EQ(r.size(), 6);
  EXPECT_LT(r.norm(), 1e-12);

  // Scale +0.1: only alpha moves, by 0.1 x R^T (pbar1 - pbar0) = (0.055, 0, 0).
  LinearAlignment bigger = truth;
  bigger.scale = 2.1;
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(6);
  expected(0) = 0.055;
  EXPECT_LT((alignmentResidual(frames, T_B_C, bigger) - expected).norm(), 1e-12);

  // v0 + (0, 0.5, 0): alpha_y -= 0.5 dt, beta_y -= 0.5.
  LinearAlignment faster = truth;
  faster.velocities_body[0].y() += 0.5;
  expected.setZero();
  expected(1) = -0.5;
  expected(4) = -0.5;
  EXPECT_LT((alignmentResidual(frames, T_B_C, faster) - expected).norm(), 1e-12);

  // Gravity + (0, 0, 1): alpha_z -= dt^2 / 2, beta_z -= dt.
  LinearAlignment heavier = truth;
  heavier.gravity_c0.z() += 1.0;
  expected.setZero();
  expected(2) = -0.5;
  expected(5) = -1.0;
  EXPECT_LT((alignmentResidual(frames, T_B_C, heavier) - expected).norm(), 1e-12);

  // Two frames are 6 equations for 10 unknowns: the solver refuses.
  LinearAlignment solved;
  EXPECT_FALSE(solveLinearAlignment(frames, T_B_C, &solved));
}

TEST(VisualInertialAlignment, TangentBasisAndWorldFrame) {
  const Eigen::Vector3d g(0.3, -9.7, 1.2);
  const Eigen::Matrix<double, 3, 2> B = tangentBasis(g);
  EXPECT_LT((B.transpose() * B - Eigen::Matrix2d::Identity()).norm(), 1e-12);
  EXPECT_LT((B.transpose() * g).norm(), 1e-12);
  EXPECT_LT(
      (tangentBasis(Eigen::Vector3d(0, 0, -9.81)).transpose() * Eigen::Vector3d::UnitZ()).norm(),
      1e-12);

  const Eigen::Matrix3d R_c0_b0 = data::eulerZyxToRotation(0.4, -0.2, 1.0);
  const Eigen::Matrix3d R_W_c0 = worldFromFirstCamera(g, R_c0_b0);
  EXPECT_LT((R_W_c0 * g.normalized() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  const Eigen::Matrix3d R_W_b0 = R_W_c0 * R_c0_b0;
  EXPECT_NEAR(std::atan2(R_W_b0(1, 0), R_W_b0(0, 0)), 0.0, 1e-12);
}

TEST(VisualInertialAlignment, ExcitationByHand) {
  // Mean specific forces (1, 0, 9.81) and (3, 0, 9.81): x has sample std sqrt(2).
  std::vector<AlignmentFrame> frames(3);
  frames[1].imu_from_previous = constantForce(Eigen::Vector3d(1, 0, 9.81), 0.2);
  frames[2].imu_from_previous = constantForce(Eigen::Vector3d(3, 0, 9.81), 0.2);
  EXPECT_NEAR(imuExcitation(frames), std::sqrt(2.0), 1e-9);
}

// Alignment frames from the scene's true camera poses, scaled by 1 / true_scale.
std::vector<AlignmentFrame> trueFrames(const test::InitScene& scene, double true_scale) {
  const auto camera = [&](size_t k) {
    return Eigen::Isometry3d(Eigen::Translation3d(scene.truth[k].p_W_B) * scene.truth[k].q_W_B) *
           scene.T_B_C;
  };
  std::vector<AlignmentFrame> frames(scene.frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Isometry3d T = camera(0).inverse() * camera(k);
    frames[k].R_c0_c = T.rotation();
    frames[k].p_c0_c = T.translation() / true_scale;
    frames[k].imu_from_previous = scene.frames[k].imu_from_previous;
  }
  return frames;
}

TEST(VisualInertialAlignment, GyroBiasFromTrueRotations) {
  test::InitSceneOptions options;
  options.gyro_bias = Eigen::Vector3d(0.01, -0.02, 0.015);
  test::InitScene scene = test::makeInitScene(options);
  const auto frames = trueFrames(scene, 1.0);
  Eigen::Vector3d bias;
  ASSERT_TRUE(solveGyroBias(frames, scene.T_B_C.rotation(), &bias));
  // First order in the bias: already within 1e-5 of 0.027 rad/s.
  EXPECT_LT((bias - options.gyro_bias).norm(), 1e-5);
  // Mixed linearisation points (half the preintegrations repropagated) give the same answer.
  for (size_t k = 1; k < frames.size(); k += 2)
    frames[k].imu_from_previous->repropagate(Eigen::Vector3d::Zero(), bias);
  Eigen::Vector3d mixed;
  ASSERT_TRUE(solveGyroBias(frames, scene.T_B_C.rotation(), &mixed));
  EXPECT_LT((mixed - options.gyro_bias).norm(), 1e-5);
  for (size_t k = 1; k < frames.size(); ++k)
    frames[k].imu_from_previous->repropagate(Eigen::Vector3d::Zero(), mixed);
  Eigen::Vector3d second;
  ASSERT_TRUE(solveGyroBias(frames, scene.T_B_C.rotation(), &second));
  // The floor is the midpoint integration's own error at 200 Hz on this trajectory (~1e-6).
  EXPECT_LT((second - options.gyro_bias).norm(), 5e-6);

  // No rotation information (no frames with IMU) is refused, not NaN.
  std::vector<AlignmentFrame> lonely(1);
  EXPECT_FALSE(solveGyroBias(lonely, Eigen::Matrix3d::Identity(), &bias));
}

TEST(VisualInertialAlignment, LinearSolveAndGravityRefinementOnExactWindow) {
  const test::InitScene scene = test::makeInitScene();
  const double true_scale = 0.37;  // metric / SfM
  const auto frames = trueFrames(scene, true_scale);
  // Truth in c0: gravity and body-frame velocities.
  const Eigen::Matrix3d R_W_c0 = scene.truth[0].q_W_B.toRotationMatrix() * scene.T_B_C.rotation();
  const Eigen::Vector3d g_c0 = R_W_c0.transpose() * Eigen::Vector3d(0, 0, -9.81);

  // Tolerances: the 200 Hz midpoint preintegration differs from the analytic trajectory by
  // ~1e-5 relative (measured: scale 2e-5 relative, velocities 1.1e-5 m/s).
  LinearAlignment linear;
  ASSERT_TRUE(solveLinearAlignment(frames, scene.T_B_C, &linear));
  EXPECT_NEAR(linear.scale, true_scale, 1e-4 * true_scale);
  EXPECT_LT((linear.gravity_c0 - g_c0).norm(), 1e-4);
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Vector3d v_true = scene.truth[k].q_W_B.conjugate() * scene.truth[k].v_W;
    EXPECT_LT((linear.velocities_body[k] - v_true).norm(), 1e-4) << k;
  }
  EXPECT_LT(alignmentResidual(frames, scene.T_B_C, linear).norm(), 1e-5);

  // Refinement from a guess 5 deg off and 10% short converges to the truth with |g| = 9.81.
  const Eigen::Vector3d guess =
      0.9 * (Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitX()) * g_c0);
  LinearAlignment refined;
  ASSERT_TRUE(refineGravity(frames, scene.T_B_C, guess, 4, &refined));
  EXPECT_NEAR(refined.gravity_c0.norm(), 9.81, 1e-12);
  EXPECT_LT((refined.gravity_c0 - g_c0).norm(), 1e-4);
  EXPECT_NEAR(refined.scale, true_scale, 1e-4 * true_scale);

  EXPECT_FALSE(refineGravity(frames, scene.T_B_C, Eigen::Vector3d::Zero(), 4, &refined));
}

TEST(VisualInertialAlignment, LeastSquaresStdByHand) {
  // Line y = a + s t through (0, 0), (1, 1), (2, 3): s = 1.5, a = -1/6, residuals (1/6, -1/3,
  // 1/6), sigma^2 = (1/36 + 1/9 + 1/36) / (3 - 2) = 1/6, var(s) = sigma^2 / sum (t - 1)^2 = 1/12.
  Eigen::MatrixXd A(3, 2);
  A << 1, 0, 1, 1, 1, 2;
  const Eigen::Vector3d b(0, 1, 3);
  const Eigen::Vector2d x(-1.0 / 6.0, 1.5);
  EXPECT_NEAR(leastSquaresStd(A, b, x, 1), std::sqrt(1.0 / 12.0), 1e-12);
  // var(a) = sigma^2 (1/n + mean(t)^2 / sum (t - 1)^2) = 1/6 (1/3 + 1/2) = 5/36.
  EXPECT_NEAR(leastSquaresStd(A, b, x, 0), std::sqrt(5.0 / 36.0), 1e-12);
  // No redundancy: nothing to estimate the noise from.
  EXPECT_EQ(leastSquaresStd(A.topRows(2), b.head<2>(), x, 1), 0.0);
  // Two equal columns: the unknown is undetermined.
  Eigen::MatrixXd same(3, 2);
  same << 1, 1, 1, 1, 1, 1;
  EXPECT_TRUE(std::isinf(leastSquaresStd(same, b, x, 1)));
}

TEST(VisualInertialAlignment, ScaleStdIsSmallOnAnExactWindowAndGrowsWithDisagreement) {
  const test::InitScene scene = test::makeInitScene();
  const double true_scale = 0.37;
  auto frames = trueFrames(scene, true_scale);
  const Eigen::Vector3d g_c0 = (scene.truth[0].q_W_B.toRotationMatrix() * scene.T_B_C.rotation())
                                   .transpose() * Eigen::Vector3d(0, 0, -9.81);
  LinearAlignment exact;
  ASSERT_TRUE(refineGravity(frames, scene.T_B_C, g_c0, 4, &exact));
  EXPECT_LT(exact.scale_std / exact.scale, 1e-3);

  // SfM positions that do not follow the IMU (a few centimetres of zig-zag, as a window tracking
  // moving objects gives): the fit degrades and says so; twice the disagreement, about twice the std.
  auto shaken = [&](double amplitude) {
    auto moved = frames;
    for (size_t k = 1; k < moved.size(); ++k)
      moved[k].p_c0_c += (k % 2 ? amplitude : -amplitude) * Eigen::Vector3d(1, -0.5, 0.3) / true_scale;
    LinearAlignment out;
    EXPECT_TRUE(refineGravity(moved, scene.T_B_C, g_c0, 4, &out));
    return out.scale_std / out.scale;
  };
  const double small = shaken(0.01), large = shaken(0.02);
  EXPECT_GT(small, 20 * exact.scale_std / exact.scale);
  EXPECT_NEAR(large / small, 2.0, 0.5);
}

}  // namespace
}  // namespace adugs::vio

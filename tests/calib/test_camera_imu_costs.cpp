// The camera-IMU residuals are autodiff; these checks compare their Jacobians (in particular the
// time-offset one, which flows through the spline parameter u) with central differences.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "calib/camera_imu/camera_imu_costs.h"
#include "tests/calib/synthetic_views.h"

namespace adugs::calib {
namespace {

// Jacobian of every block by central differences vs the cost function's own.
void expectJacobiansMatchNumeric(const ceres::CostFunction& cost,
                                 std::vector<std::vector<double>> params, double tol) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  std::vector<std::vector<double>> jac(sizes.size());
  std::vector<double*> jptrs;
  for (size_t b = 0; b < sizes.size(); ++b) {
    jac[b].resize(nr * sizes[b]);
    jptrs.push_back(jac[b].data());
  }
  std::vector<double> r(nr), rp(nr), rm(nr);
  ASSERT_TRUE(cost.Evaluate(ptrs.data(), r.data(), jptrs.data()));
  const double h = 1e-6;
  for (size_t b = 0; b < sizes.size(); ++b)
    for (int k = 0; k < sizes[b]; ++k) {
      const double keep = params[b][k];
      params[b][k] = keep + h;
      cost.Evaluate(ptrs.data(), rp.data(), nullptr);
      params[b][k] = keep - h;
      cost.Evaluate(ptrs.data(), rm.data(), nullptr);
      params[b][k] = keep;
      for (int i = 0; i < nr; ++i) {
        const double numeric = (rp[i] - rm[i]) / (2 * h);
        EXPECT_NEAR(jac[b][i * sizes[b] + k], numeric, tol * (1 + std::abs(numeric)))
            << "block " << b << " param " << k << " residual " << i;
      }
    }
}

std::vector<std::vector<double>> splineBlocks(std::mt19937& rng, bool positions) {
  std::normal_distribution<double> n(0, 1);
  std::vector<std::vector<double>> blocks;
  for (int j = 0; j < 4; ++j) {
    Eigen::Quaterniond q(Eigen::AngleAxisd(0.1 * j + 0.05 * n(rng),
                                           Eigen::Vector3d(0.2 * n(rng), 0.3, 1).normalized()));
    blocks.push_back({q.w(), q.x(), q.y(), q.z()});
  }
  if (positions)
    for (int j = 0; j < 4; ++j)
      blocks.push_back({0.3 + 0.02 * j + 0.01 * n(rng), 0.3 + 0.01 * n(rng), -0.9});
  return blocks;
}

TEST(CameraImuCosts, FrameReprojectionJacobiansIncludingTimeOffset) {
  std::mt19937 rng(2);
  const PinholeCamera cam = synth::eurocLikeCamera();
  FrameReprojection f{0.021, 20.0, &cam, {}, 1.0};
  f.corners.push_back({Eigen::Vector3d(0.2, 0.3, 0), Eigen::Vector2d(300, 200), 1.0});
  f.corners.push_back({Eigen::Vector3d(0.5, 0.1, 0), Eigen::Vector2d(400, 260), 0.7});
  auto params = splineBlocks(rng, true);
  // Camera looking down the target's -z from above it.
  const Eigen::Quaterniond q_C_I(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()));
  for (auto& p : params)
    if (p.size() == 3) p[2] = 1.0;  // IMU 1 m above the board
  params.push_back({q_C_I.w(), q_C_I.x(), q_C_I.y(), q_C_I.z()});
  params.push_back({0.02, -0.05, 0.01});
  params.push_back({0.004});
  const ceres::AutoDiffCostFunction<FrameReprojection, ceres::DYNAMIC, 4, 4, 4, 4, 3, 3, 3, 3, 4, 3,
                                    1>
      cost(new FrameReprojection(f), 4);
  expectJacobiansMatchNumeric(cost, params, 1e-5);
  // Not a trivial pass: the corners are in front of the camera and the offset moves them.
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  std::vector<double> r(4), j_shift(4);
  std::vector<double*> jacobians(params.size(), nullptr);
  jacobians.back() = j_shift.data();
  ASSERT_TRUE(cost.Evaluate(ptrs.data(), r.data(), jacobians.data()));
  EXPECT_GT(Eigen::Vector4d(r.data()).norm(), 1.0);
  EXPECT_GT(Eigen::Vector4d(j_shift.data()).norm(), 10.0);  // px per second of offset
}

// A corner behind the camera has no reprojection error: the evaluation fails (a zero residual
// made "board behind the camera" a perfect fit: RMS 0.000 px, 11 m translation on EuRoC's
// first 3 s), and project() says which corners were behind.
TEST(CameraImuCosts, CornerBehindTheCameraFailsTheEvaluation) {
  std::mt19937 rng(2);
  const PinholeCamera cam = synth::eurocLikeCamera();
  FrameReprojection f{0.021, 20.0, &cam, {}, 1.0};
  f.corners.push_back({Eigen::Vector3d(0.2, 0.3, 0), Eigen::Vector2d(300, 200), 1.0});
  f.corners.push_back({Eigen::Vector3d(0.5, 0.1, 0), Eigen::Vector2d(400, 260), 1.0});
  auto params = splineBlocks(rng, true);
  const Eigen::Quaterniond q_C_I(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  for (auto& p : params)
    if (p.size() == 3) p[2] = 1.0;  // IMU 1 m above the board, camera looking down
  params.push_back({q_C_I.w(), q_C_I.x(), q_C_I.y(), q_C_I.z()});
  params.push_back({0, 0, 0});
  params.push_back({0});
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  auto eval = [&](std::vector<double>& r, std::vector<bool>& behind) {
    return f.project(ptrs[0], ptrs[1], ptrs[2], ptrs[3], ptrs[4], ptrs[5], ptrs[6], ptrs[7],
                     ptrs[8], ptrs[9], ptrs[10], r.data(), &behind);
  };
  std::vector<double> r(4);
  std::vector<bool> behind;
  EXPECT_EQ(eval(r, behind), 0);
  EXPECT_TRUE(f(ptrs[0], ptrs[1], ptrs[2], ptrs[3], ptrs[4], ptrs[5], ptrs[6], ptrs[7], ptrs[8],
                ptrs[9], ptrs[10], r.data()));
  // Move the camera 2 m behind its own image plane: the board is now behind it.
  params[9][2] = -2.0;
  EXPECT_EQ(eval(r, behind), 2);
  EXPECT_EQ(behind, std::vector<bool>({true, true}));
  EXPECT_FALSE(f(ptrs[0], ptrs[1], ptrs[2], ptrs[3], ptrs[4], ptrs[5], ptrs[6], ptrs[7], ptrs[8],
                 ptrs[9], ptrs[10], r.data()));
}

TEST(CameraImuCosts, GyroAndAccelJacobians) {
  std::mt19937 rng(4);
  auto rot = splineBlocks(rng, false);
  rot.push_back({0.01, -0.02, 0.03});
  rot.push_back({0.02, -0.01, 0.01});
  const ceres::AutoDiffCostFunction<GyroResidual, 3, 4, 4, 4, 4, 3, 3> gyro(
      new GyroResidual{0.37, 20.0, Eigen::Vector3d(0.1, 0.2, -0.3), 400.0, 0.25});
  expectJacobiansMatchNumeric(gyro, rot, 1e-5);

  auto all = splineBlocks(rng, true);
  all.push_back({0.05, 0.0, -0.02});
  all.push_back({0.04, 0.01, -0.03});
  all.push_back({0.0, 0.6, -0.8});
  const ceres::AutoDiffCostFunction<AccelResidual, 3, 4, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3> accel(
      new AccelResidual{0.61, 20.0, Eigen::Vector3d(0.3, 9.7, 0.2), 35.0, 9.81, 0.6});
  expectJacobiansMatchNumeric(accel, all, 1e-5);
}

}  // namespace
}  // namespace adugs::calib

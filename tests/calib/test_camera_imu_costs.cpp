// The camera-IMU residuals are autodiff; these checks compare their Jacobians (in particular the
// time-offset one, which flows through the spline parameter u) with central differences of the
// same functions, and then values and Jacobians with a second formulation written apart.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <opencv2/calib3d.hpp>
#include <random>
#include <set>
#include <vector>

#include "calib/camera_imu/camera_imu_costs.h"
#include "tests/calib/synthetic_views.h"

namespace adugs::calib {
namespace {

// The cost's residuals and its Jacobian of every block (row-major, residuals x block size).
struct Evaluated {
  std::vector<double> r;
  std::vector<std::vector<double>> jac;
};
Evaluated evaluate(const ceres::CostFunction& cost, std::vector<std::vector<double>>& params) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  Evaluated e{std::vector<double>(nr), std::vector<std::vector<double>>(sizes.size())};
  std::vector<double*> jptrs;
  for (size_t b = 0; b < sizes.size(); ++b) {
    e.jac[b].resize(nr * sizes[b]);
    jptrs.push_back(e.jac[b].data());
  }
  EXPECT_TRUE(cost.Evaluate(ptrs.data(), e.r.data(), jptrs.data()));
  return e;
}

// Jacobian of every block by central differences vs the cost function's own.
void expectJacobiansMatchNumeric(const ceres::CostFunction& cost,
                                 std::vector<std::vector<double>> params, double tol) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  const std::vector<std::vector<double>> jac = evaluate(cost, params).jac;
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  std::vector<double> rp(nr), rm(nr);
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
  const CalibCamera cam = synth::eurocLikeCamera();
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
  const CalibCamera cam = synth::eurocLikeCamera();
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

// ---- A second formulation of the three residuals, written from the textbook definitions with
// Eigen and OpenCV and none of the templated spline or projection code: the uniform cubic
// B-spline through its blending matrix, the body angular velocity and the acceleration by
// differencing the curve in time, the projection by cv::projectPoints. Numeric differences of it,
// on the rotations' tangent spaces, must equal the costs' autodiff Jacobians. The checks above
// only catch code that is not smooth; a smooth but wrong formula (an angular velocity in the
// world frame, a transposed rotation, the time offset's sign, a swapped distortion term) passes
// them and fails these.
namespace second {

using Blocks = std::vector<std::vector<double>>;

struct Curve {
  std::array<Eigen::Quaterniond, 4> q;
  std::array<Eigen::Vector3d, 4> p;
  double dt = 1;
};

Curve curveOf(const Blocks& b, bool positions, double inv_dt) {
  Curve c;
  for (int j = 0; j < 4; ++j) c.q[j] = Eigen::Quaterniond(b[j][0], b[j][1], b[j][2], b[j][3]).normalized();
  for (int j = 0; j < 4; ++j) c.p[j] = positions ? Eigen::Vector3d(b[4 + j].data()) : Eigen::Vector3d::Zero();
  c.dt = 1 / inv_dt;
  return c;
}

// Cumulative weights [1, b1+b2+b3, b2+b3, b3] of the basis [1 u u^2 u^3] M.
Eigen::Vector4d cumulativeWeights(double u) {
  Eigen::Matrix4d m;
  m << 1, 4, 1, 0, -3, 0, 3, 0, 3, -6, 3, 0, -1, 3, -3, 1;
  const Eigen::RowVector4d b = Eigen::RowVector4d(1, u, u * u, u * u * u) * (m / 6);
  return {1, b(1) + b(2) + b(3), b(2) + b(3), b(3)};
}

Eigen::Matrix3d rotationAt(const Curve& c, double u) {
  const Eigen::Vector4d w = cumulativeWeights(u);
  Eigen::Matrix3d r = c.q[0].toRotationMatrix();
  for (int j = 1; j < 4; ++j) {
    const Eigen::AngleAxisd d(c.q[j - 1].toRotationMatrix().transpose() * c.q[j].toRotationMatrix());
    r = r * Eigen::AngleAxisd(w(j) * d.angle(), d.axis()).toRotationMatrix();
  }
  return r;
}

Eigen::Vector3d positionAt(const Curve& c, double u) {
  const Eigen::Vector4d w = cumulativeWeights(u);
  Eigen::Vector3d p = c.p[0];
  for (int j = 1; j < 4; ++j) p += w(j) * (c.p[j] - c.p[j - 1]);
  return p;
}

// R^T dR/dt = [omega]x, from the rotation one step either side.
Eigen::Vector3d bodyRateAt(const Curve& c, double u) {
  const double h = 1e-4;  // truncation error ~h^2, 1e-9 relative
  const Eigen::AngleAxisd step(rotationAt(c, u - h).transpose() * rotationAt(c, u + h));
  return step.angle() * step.axis() / (2 * h * c.dt);
}

// The curve is cubic in u: the central second difference is exact up to rounding, so a wide
// step keeps the rounding small.
Eigen::Vector3d accelerationAt(const Curve& c, double u) {
  const double h = 0.1;
  return (positionAt(c, u + h) - 2 * positionAt(c, u) + positionAt(c, u - h)) / (h * h * c.dt * c.dt);
}

Eigen::Vector3d blend(const Blocks& b, size_t first, double w) {
  return (1 - w) * Eigen::Vector3d(b[first].data()) + w * Eigen::Vector3d(b[first + 1].data());
}

Eigen::VectorXd gyro(const GyroResidual& g, const Blocks& b) {
  const Curve c = curveOf(b, false, g.inv_dt);
  return (bodyRateAt(c, g.u) + blend(b, 4, g.bias_w) - g.measured) * g.inv_sigma;
}

Eigen::VectorXd accel(const AccelResidual& a, const Blocks& b) {
  const Curve c = curveOf(b, true, a.inv_dt);
  const Eigen::Vector3d specific_T = accelerationAt(c, a.u) - a.gravity * Eigen::Vector3d(b[10].data());
  return (rotationAt(c, a.u).transpose() * specific_T + blend(b, 8, a.bias_w) - a.measured) * a.inv_sigma;
}

Eigen::VectorXd reprojection(const FrameReprojection& f, const Blocks& b) {
  const Curve c = curveOf(b, true, f.inv_dt);
  const double u = (f.t_cam_in_segment + b[10][0]) * f.inv_dt;
  const Eigen::Matrix3d r_T_I = rotationAt(c, u);
  const Eigen::Vector3d p_T_I = positionAt(c, u);
  const Eigen::Matrix3d r_C_I = Eigen::Quaterniond(b[8][0], b[8][1], b[8][2], b[8][3]).normalized().toRotationMatrix();
  std::vector<cv::Point3d> in_camera;
  for (const FrameReprojection::Corner& k : f.corners) {
    const Eigen::Vector3d p_C = r_C_I * (r_T_I.transpose() * (k.point_T - p_T_I)) + Eigen::Vector3d(b[9].data());
    in_camera.emplace_back(p_C.x(), p_C.y(), p_C.z());
  }
  const auto& q = f.camera->params;
  const cv::Matx33d k_matrix(q[0], 0, q[2], 0, q[1], q[3], 0, 0, 1);
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(in_camera, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k_matrix,
                    std::vector<double>{q[4], q[5], q[6], q[7]}, pixels);
  Eigen::VectorXd r(2 * f.corners.size());
  for (size_t k = 0; k < f.corners.size(); ++k) {
    const double w = f.corners[k].weight * f.inv_sigma_px;
    r(2 * k) = (pixels[k].x - f.corners[k].pixel.x()) * w;
    r(2 * k + 1) = (pixels[k].y - f.corners[k].pixel.y()) * w;
  }
  return r;
}

// The cost's residuals equal the second formulation's, and its Jacobian of every block equals
// central differences of the second formulation: on the quaternion manifold's tangent space for
// the rotation blocks (the calibrator's parameterisation; the raw 4-vector directions off the
// unit sphere are not part of the problem), plain for the others.
void expectSameAsSecondFormulation(const ceres::CostFunction& cost, Blocks params,
                                   const std::function<Eigen::VectorXd(const Blocks&)>& formulation,
                                   const std::set<size_t>& quaternion_blocks) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  const Evaluated e = evaluate(cost, params);
  const Eigen::Map<const Eigen::VectorXd> r(e.r.data(), nr);
  const std::vector<std::vector<double>>& jac = e.jac;
  const Eigen::VectorXd r2 = formulation(params);
  ASSERT_EQ(r2.size(), nr);
  for (int i = 0; i < nr; ++i) EXPECT_NEAR(r(i), r2(i), 1e-6 * (1 + std::abs(r2(i)))) << "residual " << i;

  const ceres::QuaternionManifold manifold;
  const double eps = 1e-4;  // truncation ~eps^2; smaller steps amplify the differenced rates' rounding
  for (size_t b = 0; b < sizes.size(); ++b) {
    const bool rotation = quaternion_blocks.count(b) > 0;
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> raw(
        jac[b].data(), nr, sizes[b]);
    Eigen::MatrixXd analytic = raw;
    if (rotation) {
      Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
      manifold.PlusJacobian(params[b].data(), plus.data());
      analytic = raw * plus;
    }
    Eigen::MatrixXd numeric(nr, analytic.cols());
    for (int k = 0; k < analytic.cols(); ++k) {
      Blocks up = params, down = params;
      if (rotation) {
        Eigen::Vector3d delta = Eigen::Vector3d::Zero();
        delta(k) = eps;
        manifold.Plus(params[b].data(), delta.data(), up[b].data());
        delta(k) = -eps;
        manifold.Plus(params[b].data(), delta.data(), down[b].data());
      } else {
        up[b][k] += eps;
        down[b][k] -= eps;
      }
      numeric.col(k) = (formulation(up) - formulation(down)) / (2 * eps);
    }
    const double scale = 1 + numeric.cwiseAbs().maxCoeff();
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-5 * scale)
        << "block " << b << "\nautodiff\n" << analytic << "\nsecond formulation\n" << numeric;
    EXPECT_GT(numeric.norm(), 0) << "block " << b << " does not move the residual: nothing compared";
  }
}

}  // namespace second

TEST(CameraImuCosts, GyroMatchesASecondFormulation) {
  std::mt19937 rng(7);
  auto blocks = splineBlocks(rng, false);
  blocks.push_back({0.01, -0.02, 0.03});
  blocks.push_back({0.02, -0.01, 0.01});
  const GyroResidual g{0.37, 20.0, Eigen::Vector3d(0.1, 0.2, -0.3), 400.0, 0.25};
  const ceres::AutoDiffCostFunction<GyroResidual, 3, 4, 4, 4, 4, 3, 3> cost(new GyroResidual(g));
  second::expectSameAsSecondFormulation(
      cost, blocks, [&](const second::Blocks& b) { return second::gyro(g, b); }, {0, 1, 2, 3});
}

TEST(CameraImuCosts, AccelMatchesASecondFormulation) {
  std::mt19937 rng(8);
  auto blocks = splineBlocks(rng, true);
  blocks.push_back({0.05, 0.0, -0.02});
  blocks.push_back({0.04, 0.01, -0.03});
  blocks.push_back({0.0, 0.6, -0.8});
  const AccelResidual a{0.61, 20.0, Eigen::Vector3d(0.3, 9.7, 0.2), 35.0, 9.81, 0.6};
  const ceres::AutoDiffCostFunction<AccelResidual, 3, 4, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3> cost(new AccelResidual(a));
  second::expectSameAsSecondFormulation(
      cost, blocks, [&](const second::Blocks& b) { return second::accel(a, b); }, {0, 1, 2, 3});
}

TEST(CameraImuCosts, FrameReprojectionMatchesASecondFormulation) {
  std::mt19937 rng(9);
  const CalibCamera cam = synth::eurocLikeCamera();
  FrameReprojection f{0.021, 20.0, &cam, {}, 2.0};
  f.corners.push_back({Eigen::Vector3d(0.2, 0.3, 0), Eigen::Vector2d(300, 200), 1.0});
  f.corners.push_back({Eigen::Vector3d(0.5, 0.1, 0), Eigen::Vector2d(400, 260), 0.7});
  f.corners.push_back({Eigen::Vector3d(-0.1, 0.6, 0), Eigen::Vector2d(250, 330), 1.0});
  auto blocks = splineBlocks(rng, true);
  for (auto& p : blocks)
    if (p.size() == 3) p[2] = 1.0;  // IMU 1 m above the board, the camera looking down at it
  const Eigen::Quaterniond q_C_I(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()));
  blocks.push_back({q_C_I.w(), q_C_I.x(), q_C_I.y(), q_C_I.z()});
  blocks.push_back({0.02, -0.05, 0.01});
  blocks.push_back({0.004});
  const ceres::AutoDiffCostFunction<FrameReprojection, ceres::DYNAMIC, 4, 4, 4, 4, 3, 3, 3, 3, 4, 3, 1> cost(
      new FrameReprojection(f), 6);
  second::expectSameAsSecondFormulation(
      cost, blocks, [&](const second::Blocks& b) { return second::reprojection(f, b); }, {0, 1, 2, 3, 8});
}

}  // namespace
}  // namespace adugs::calib

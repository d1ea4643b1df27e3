// Hand-worked cases of the cumulative cubic B-spline of the camera-IMU calibration.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "calib/camera_imu/camera_imu_spline.h"

namespace adugs::calib {
namespace {

TEST(CameraImuSpline, CumulativeBasisHandValues) {
  double b[4], db[4], ddb[4];
  cumulativeBasis(0.0, b, db, ddb);
  // At u = 0 the (non-cumulative) weights are 1/6, 4/6, 1/6, 0: cumulative 1, 5/6, 1/6, 0.
  EXPECT_DOUBLE_EQ(b[0], 1.0);
  EXPECT_DOUBLE_EQ(b[1], 5.0 / 6);
  EXPECT_DOUBLE_EQ(b[2], 1.0 / 6);
  EXPECT_DOUBLE_EQ(b[3], 0.0);
  cumulativeBasis(1.0, b, db, ddb);
  EXPECT_DOUBLE_EQ(b[1], 1.0);  // at u = 1: weights 0, 1/6, 4/6, 1/6
  EXPECT_DOUBLE_EQ(b[2], 5.0 / 6);
  EXPECT_DOUBLE_EQ(b[3], 1.0 / 6);
  cumulativeBasis(0.5, b, db, ddb);
  EXPECT_DOUBLE_EQ(b[3], 0.125 / 6);
  EXPECT_DOUBLE_EQ(db[3], 0.125);
  EXPECT_DOUBLE_EQ(ddb[1], -0.5);
}

TEST(CameraImuSpline, BasisDerivativesMatchFiniteDifferences) {
  const double h = 1e-6;
  for (double u : {0.0, 0.21, 0.5, 0.77, 1.0}) {
    double b[4], db[4], ddb[4], bp[4], bm[4], dbp[4], dbm[4], tmp[4];
    cumulativeBasis(u, b, db, ddb);
    cumulativeBasis(u + h, bp, dbp, tmp);
    cumulativeBasis(u - h, bm, dbm, tmp);
    for (int j = 0; j < 4; ++j) {
      EXPECT_NEAR(db[j], (bp[j] - bm[j]) / (2 * h), 1e-8) << "u " << u << " j " << j;
      EXPECT_NEAR(ddb[j], (dbp[j] - dbm[j]) / (2 * h), 1e-8) << "u " << u << " j " << j;
    }
  }
}

// A cubic B-spline reproduces polynomials up to degree 3. With control points c_j = tau_j^2 -
// dt^2/3 at tau_j = (j - 1) dt (the cubic B-spline kernel has variance dt^2/3), the curve is t^2.
TEST(CameraImuSpline, PositionReproducesQuadratic) {
  const double dt = 0.1;
  double c[4][3];
  const int seg = 5;
  for (int j = 0; j < 4; ++j) {
    const double tau = (seg + j - 1) * dt;
    c[j][0] = tau * tau - dt * dt / 3;
    c[j][1] = 2 * tau + 1;  // linear
    c[j][2] = -3;           // constant
  }
  const double* cp[4] = {c[0], c[1], c[2], c[3]};
  for (double u : {0.0, 0.3, 0.9}) {
    const double t = (seg + u) * dt;
    double p[3], v[3], a[3];
    evalPositionSpline(cp, u, 1 / dt, p, v, a);
    EXPECT_NEAR(p[0], t * t, 1e-12);
    EXPECT_NEAR(v[0], 2 * t, 1e-10);
    EXPECT_NEAR(a[0], 2.0, 1e-8);
    EXPECT_NEAR(p[1], 2 * t + 1, 1e-12);
    EXPECT_NEAR(v[1], 2.0, 1e-10);
    EXPECT_NEAR(a[1], 0.0, 1e-8);
    EXPECT_NEAR(p[2], -3.0, 1e-12);
  }
}

Eigen::Quaterniond toEigen(const double q[4]) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

// Rotation at a constant rate about one axis: control rotations Exp(alpha tau_j axis) give exactly
// Exp(alpha t axis) (the 1-D spline reproduces the linear angle) and omega = alpha axis.
TEST(CameraImuSpline, RotationReproducesConstantRate) {
  const double dt = 0.05, alpha = 1.3;
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  double q[4][4];
  for (int j = 0; j < 4; ++j) {
    const Eigen::Quaterniond e(Eigen::AngleAxisd(alpha * (j - 1) * dt, axis));
    q[j][0] = e.w(), q[j][1] = e.x(), q[j][2] = e.y(), q[j][3] = e.z();
  }
  const double* qp[4] = {q[0], q[1], q[2], q[3]};
  for (double u : {0.0, 0.4, 1.0}) {
    double r[4], w[3];
    evalRotationSpline(qp, u, 1 / dt, r, w);
    const Eigen::Quaterniond expect(Eigen::AngleAxisd(alpha * u * dt, axis));
    EXPECT_LT(toEigen(r).angularDistance(expect), 1e-12);
    EXPECT_LT((Eigen::Vector3d(w[0], w[1], w[2]) - alpha * axis).norm(), 1e-10);
  }
}

// General control rotations: omega from the recursion vs the finite difference of R(t).
TEST(CameraImuSpline, AngularVelocityMatchesFiniteDifference) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 0.4);
  const double dt = 0.1;
  double q[4][4];
  for (auto& qj : q) {
    const Eigen::Quaterniond e(Eigen::AngleAxisd(
        std::abs(n(rng)) + 0.1, Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()));
    qj[0] = e.w(), qj[1] = e.x(), qj[2] = e.y(), qj[3] = e.z();
  }
  const double* qp[4] = {q[0], q[1], q[2], q[3]};
  const double h = 1e-6;
  for (double u : {0.1, 0.5, 0.9}) {
    double r[4], rp[4], rm[4], w[3];
    evalRotationSpline(qp, u, 1 / dt, r, w);
    evalRotationSpline(qp, u + h, 1 / dt, rp, static_cast<double*>(nullptr));
    evalRotationSpline(qp, u - h, 1 / dt, rm, static_cast<double*>(nullptr));
    const Eigen::AngleAxisd d(toEigen(rm).conjugate() * toEigen(rp));
    // Central difference in the body frame at the middle: (Log(R(t-h)^T R(t+h))) / (2 h dt).
    const Eigen::Vector3d numeric = d.axis() * d.angle() / (2 * h * dt);
    EXPECT_LT((Eigen::Vector3d(w[0], w[1], w[2]) - numeric).norm(), 1e-5) << "u " << u;
    EXPECT_NEAR(toEigen(r).norm(), 1.0, 1e-12);
  }
}

TEST(CameraImuSpline, LocateOnSpline) {
  const SplineLocation a = locateOnSpline(1.25, 1.0, 0.1);
  EXPECT_EQ(a.segment, 2);
  EXPECT_NEAR(a.u, 0.5, 1e-9);
  const SplineLocation b = locateOnSpline(0.95, 1.0, 0.1);
  EXPECT_EQ(b.segment, -1);
  EXPECT_NEAR(b.u, 0.5, 1e-9);
}

}  // namespace
}  // namespace adugs::calib

#pragma once
// Uniform cumulative cubic B-spline for the IMU pose trajectory of the camera-IMU calibration,
// templated so Ceres can autodiff it (the time argument u may be a Jet: the time offset).
//
// Control points c_0..c_{N-1}, knot spacing dt, first knot t0. Segment i covers
// [t0 + i dt, t0 + (i+1) dt) and uses c_i..c_{i+3}; with u = (t - t0 - i dt) / dt in [0, 1):
//   position  p(u) = c_i + sum_{j=1..3} Bc_j(u) (c_{i+j} - c_{i+j-1})
//   rotation  R(u) = R_i * prod_{j=1..3} Exp(Bc_j(u) d_j),  d_j = Log(R_{i+j-1}^T R_{i+j})
// with the cumulative basis Bc(u) = [1, (5 + 3u - 3u^2 + u^3)/6, (1 + 3u + 3u^2 - 2u^3)/6, u^3/6].
// The curve at the start of segment i is close to control point i + 1, so control point j
// "belongs" to time t0 + (j - 1) dt.
// Body angular velocity (R^T dR/dt = [w]x), by the recursion of Sommer et al. 2020:
//   w_0 = 0,  w_j = A_j^T w_{j-1} + dBc_j/dt d_j,  A_j = Exp(Bc_j d_j).
// Rotations are ceres-order quaternions [w, x, y, z].
#include <ceres/rotation.h>

namespace adugs::calib {

// Cumulative basis and its first two derivatives with respect to u.
template <typename T>
void cumulativeBasis(const T& u, T b[4], T db[4], T ddb[4]) {
  const T u2 = u * u, u3 = u2 * u;
  b[0] = T(1);
  b[1] = (T(5) + T(3) * u - T(3) * u2 + u3) / T(6);
  b[2] = (T(1) + T(3) * u + T(3) * u2 - T(2) * u3) / T(6);
  b[3] = u3 / T(6);
  db[0] = T(0);
  db[1] = (T(3) - T(6) * u + T(3) * u2) / T(6);
  db[2] = (T(3) + T(6) * u - T(6) * u2) / T(6);
  db[3] = u2 / T(2);
  ddb[0] = T(0);
  ddb[1] = u - T(1);
  ddb[2] = T(1) - T(2) * u;
  ddb[3] = u;
}

// Position, velocity and acceleration (per second: inv_dt = 1 / dt) of the R^3 spline.
// vel / acc may be null.
template <typename T>
void evalPositionSpline(const T* const c[4], const T& u, double inv_dt, T p[3], T* vel, T* acc) {
  T b[4], db[4], ddb[4];
  cumulativeBasis(u, b, db, ddb);
  for (int k = 0; k < 3; ++k) {
    p[k] = c[0][k];
    if (vel) vel[k] = T(0);
    if (acc) acc[k] = T(0);
    for (int j = 1; j < 4; ++j) {
      const T diff = c[j][k] - c[j - 1][k];
      p[k] += b[j] * diff;
      if (vel) vel[k] += db[j] * diff * T(inv_dt);
      if (acc) acc[k] += ddb[j] * diff * T(inv_dt * inv_dt);
    }
  }
}

// Rotation (quaternion, w first) and body angular velocity (may be null) of the SO(3) spline.
template <typename T>
void evalRotationSpline(const T* const q[4], const T& u, double inv_dt, T q_out[4], T* omega) {
  T b[4], db[4], ddb[4];
  cumulativeBasis(u, b, db, ddb);
  T r[4] = {q[0][0], q[0][1], q[0][2], q[0][3]};
  T w[3] = {T(0), T(0), T(0)};
  for (int j = 1; j < 4; ++j) {
    // d_j = Log(q_{j-1}^-1 q_j); QuaternionToAngleAxis takes the short way round.
    const T inv_prev[4] = {q[j - 1][0], -q[j - 1][1], -q[j - 1][2], -q[j - 1][3]};
    T rel[4], d[3];
    ceres::QuaternionProduct(inv_prev, q[j], rel);
    ceres::QuaternionToAngleAxis(rel, d);
    const T scaled[3] = {b[j] * d[0], b[j] * d[1], b[j] * d[2]};
    T a[4];
    ceres::AngleAxisToQuaternion(scaled, a);
    T next[4];
    ceres::QuaternionProduct(r, a, next);
    for (int k = 0; k < 4; ++k) r[k] = next[k];
    if (omega) {
      // w <- A^T w + dB d  (rotate w by the inverse of a)
      const T a_inv[4] = {a[0], -a[1], -a[2], -a[3]};
      T rotated[3];
      ceres::UnitQuaternionRotatePoint(a_inv, w, rotated);
      for (int k = 0; k < 3; ++k) w[k] = rotated[k] + db[j] * T(inv_dt) * d[k];
    }
  }
  for (int k = 0; k < 4; ++k) q_out[k] = r[k];
  if (omega)
    for (int k = 0; k < 3; ++k) omega[k] = w[k];
}

// Where a time falls on the spline: segment index and u. Valid when 0 <= segment <= N - 4.
struct SplineLocation {
  int segment = -1;
  double u = 0;
};

inline SplineLocation locateOnSpline(double t, double t0, double dt) {
  const double s = (t - t0) / dt;
  SplineLocation loc;
  loc.segment = static_cast<int>(s >= 0 ? s : s - 1);  // floor without <cmath>
  loc.u = s - loc.segment;
  return loc;
}

}  // namespace adugs::calib

#pragma once
// Ceres residuals of the continuous-time camera-IMU calibration (autodiff). The spline is the IMU
// pose in the target frame, T_T_I(t), on the IMU clock (see camera_imu_spline.h); every term
// reads the four control rotations (quaternions w,x,y,z) and/or positions of its segment.
#include <Eigen/Core>
#include <vector>

#include "calib/camera_imu/camera_imu_spline.h"
#include "calib/calib_camera.h"

namespace adugs::calib {

// The biases are piecewise linear in time: b(t) = (1 - w) b_k + w b_k+1 between two bias knots.
template <typename T>
T blendBias(const T* b0, const T* b1, double w, int k) {
  return T(1 - w) * b0[k] + T(w) * b1[k];
}

// Gyro: omega_I(t) + b_g(t) - measured, divided by the discrete sigma.
struct GyroResidual {
  double u, inv_dt;
  Eigen::Vector3d measured;
  double inv_sigma;
  double bias_w;  // weight of the second bias knot

  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* b0, const T* b1,
                  T* r) const {
    const T* q[4] = {q0, q1, q2, q3};
    T q_T_I[4], omega[3];
    evalRotationSpline(q, T(u), inv_dt, q_T_I, omega);
    for (int k = 0; k < 3; ++k)
      r[k] = (omega[k] + blendBias(b0, b1, bias_w, k) - T(measured[k])) * T(inv_sigma);
    return true;
  }
};

// Bias random walk between consecutive bias knots: (b_k+1 - b_k) / (random_walk sqrt(dt)).
struct BiasWalkResidual {
  double inv_sigma;
  template <typename T>
  bool operator()(const T* b0, const T* b1, T* r) const {
    for (int k = 0; k < 3; ++k) r[k] = (b1[k] - b0[k]) * T(inv_sigma);
    return true;
  }
};

// Accelerometer: R_T_I^T (a_T - g |g| dir) + b_a(t) - measured, divided by the discrete sigma.
// gravity_dir is a unit vector in the target frame (2 DoF on the sphere).
struct AccelResidual {
  double u, inv_dt;
  Eigen::Vector3d measured;
  double inv_sigma;
  double gravity;
  double bias_w;

  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1,
                  const T* p2, const T* p3, const T* b0, const T* b1, const T* gravity_dir,
                  T* r) const {
    const T* q[4] = {q0, q1, q2, q3};
    const T* p[4] = {p0, p1, p2, p3};
    T q_T_I[4], pos[3], acc[3];
    evalRotationSpline(q, T(u), inv_dt, q_T_I, static_cast<T*>(nullptr));
    evalPositionSpline(p, T(u), inv_dt, pos, static_cast<T*>(nullptr), acc);
    const T specific_T[3] = {acc[0] - T(gravity) * gravity_dir[0],
                             acc[1] - T(gravity) * gravity_dir[1],
                             acc[2] - T(gravity) * gravity_dir[2]};
    const T q_I_T[4] = {q_T_I[0], -q_T_I[1], -q_T_I[2], -q_T_I[3]};
    T specific_I[3];
    ceres::UnitQuaternionRotatePoint(q_I_T, specific_T, specific_I);
    for (int k = 0; k < 3; ++k)
      r[k] = (specific_I[k] + blendBias(b0, b1, bias_w, k) - T(measured[k])) * T(inv_sigma);
    return true;
  }
};

// All corners of one frame: project p_T through T_C_I * T_T_I(t_cam + shift)^-1. The residual
// of corner k is (projected - measured) * weight_k / sigma_px (weights: robust IRLS weights).
// A corner behind the camera has no residual: the evaluation fails (Ceres then rejects the step
// that put it there). Giving it a zero residual instead made "the board behind the camera" a
// perfect fit: on a 3 s EuRoC segment the solver moved the camera 11 m to get there and the
// report said "RMS 0.000 px".
struct FrameReprojection {
  struct Corner {
    Eigen::Vector3d point_T;
    Eigen::Vector2d pixel;
    double weight = 1;
  };
  double t_cam_in_segment;  // t_cam - segment start, seconds (the shift is added on top)
  double inv_dt;
  const CalibCamera* camera;
  std::vector<Corner> corners;
  double inv_sigma_px = 1;

  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1,
                  const T* p2, const T* p3, const T* q_C_I, const T* p_C_I, const T* shift,
                  T* r) const {
    return project(q0, q1, q2, q3, p0, p1, p2, p3, q_C_I, p_C_I, shift, r, nullptr) == 0;
  }

  // Fills r for every corner (0 for a corner behind the camera, flagged in behind[k] when
  // given) and returns how many corners lie behind the camera.
  template <typename T>
  int project(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1,
              const T* p2, const T* p3, const T* q_C_I, const T* p_C_I, const T* shift, T* r,
              std::vector<bool>* behind) const {
    const T* q[4] = {q0, q1, q2, q3};
    const T* p[4] = {p0, p1, p2, p3};
    const T u = (T(t_cam_in_segment) + shift[0]) * T(inv_dt);
    T q_T_I[4], p_T_I[3];
    evalRotationSpline(q, u, inv_dt, q_T_I, static_cast<T*>(nullptr));
    evalPositionSpline(p, u, inv_dt, p_T_I, static_cast<T*>(nullptr), static_cast<T*>(nullptr));
    const T q_I_T[4] = {q_T_I[0], -q_T_I[1], -q_T_I[2], -q_T_I[3]};
    T params[8];
    for (int i = 0; i < 8; ++i) params[i] = T(camera->params[i]);
    if (behind) behind->assign(corners.size(), false);
    int behind_count = 0;
    for (size_t k = 0; k < corners.size(); ++k) {
      const Corner& c = corners[k];
      const T d[3] = {T(c.point_T.x()) - p_T_I[0], T(c.point_T.y()) - p_T_I[1],
                      T(c.point_T.z()) - p_T_I[2]};
      T p_I[3], p_C[3], uv[2];
      ceres::UnitQuaternionRotatePoint(q_I_T, d, p_I);
      ceres::UnitQuaternionRotatePoint(q_C_I, p_I, p_C);
      for (int i = 0; i < 3; ++i) p_C[i] += p_C_I[i];
      const T w = T(c.weight * inv_sigma_px);
      if (!data::projectPoint(camera->model, params, p_C, uv)) {
        r[2 * k] = r[2 * k + 1] = T(0);
        ++behind_count;
        if (behind) (*behind)[k] = true;
        continue;
      }
      r[2 * k] = (uv[0] - T(c.pixel.x())) * w;
      r[2 * k + 1] = (uv[1] - T(c.pixel.y())) * w;
    }
    return behind_count;
  }
};

}  // namespace adugs::calib

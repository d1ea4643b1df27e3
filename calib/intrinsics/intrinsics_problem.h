#pragma once
// The pieces every intrinsic-calibration solve is made of: the reprojection residual of one
// target corner (Ceres autodiff) and a view's starting pose by planar PnP.
#include <array>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Core>

#include "calib/calib_camera.h"
#include "calib/target/target_observation.h"
#include "data/camera_model.h"

namespace adugs::calib {

// Parameter blocks: focal (fu, fv), principal point (pu, pv), projection (2 parameters of the
// projection, see CalibCamera; entries the projection does not have are held constant by the
// caller), distortion (4 coefficients of the model), pose (angle-axis, translation; target ->
// camera). Residual: projected - measured [px].
struct ReprojectionCost {
  ReprojectionCost(ProjectionModel projection, DistortionModel model, const Eigen::Vector2d& pixel,
                   const Eigen::Vector3d& p_T)
      : projection_(projection), model_(model), pixel_(pixel), p_T_(p_T) {}

  template <typename T>
  bool operator()(const T* focal, const T* pp, const T* q, const T* dist, const T* pose,
                  T* residual) const {
    const T p[3] = {T(p_T_.x()), T(p_T_.y()), T(p_T_.z())};
    T p_C[3];
    ceres::AngleAxisRotatePoint(pose, p, p_C);
    for (int i = 0; i < 3; ++i) p_C[i] += pose[3 + i];
    const T params[8] = {focal[0], focal[1], pp[0], pp[1], dist[0], dist[1], dist[2], dist[3]};
    T uv[2];
    // Outside the projection's valid region (behind the camera): no residual; the evaluation
    // fails and Ceres rejects the step.
    if (!data::projectPoint(projection_, q, model_, params, p_C, uv)) return false;
    residual[0] = uv[0] - T(pixel_.x());
    residual[1] = uv[1] - T(pixel_.y());
    return true;
  }

  // The camera's projection and distortion model (its values are not used).
  static ceres::CostFunction* create(const CalibCamera& camera, const CornerObservation& c) {
    return new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 2, 2, 2, 4, 6>(
        new ReprojectionCost(camera.projection, camera.model, c.pixel, c.point));
  }

  ProjectionModel projection_;
  DistortionModel model_;
  Eigen::Vector2d pixel_;
  Eigen::Vector3d p_T_;
};

// The camera's parameter blocks in ReprojectionCost's order (focal, pp, projection, distortion).
struct CameraBlocks {
  explicit CameraBlocks(CalibCamera& camera)
      : focal(camera.params.data()), pp(camera.params.data() + 2),
        q(camera.projection_params.data()), dist(camera.params.data() + 4) {}
  double* focal;
  double* pp;
  double* q;
  double* dist;
};

using Pose6 = std::array<double, 6>;  // angle-axis, translation (target -> camera)

// Pose of a view seen by a distortion-free pinhole (f, f, cu, cv): IPPE for a planar target,
// iterative PnP otherwise. False when PnP fails or puts the target behind the camera.
bool poseFromPnp(const TargetObservation& view, double f, double cu, double cv, Pose6& pose);

// Projected minus measured for camera + pose; NaN when the corner lies behind the camera.
Eigen::Vector2d cornerResidual(const CalibCamera& camera, const Pose6& pose,
                               const CornerObservation& corner);

}  // namespace adugs::calib

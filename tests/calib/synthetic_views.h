#pragma once
// Synthetic AprilGrid views for the calibration tests: a camera looking at the grid from a
// spread of distances and angles, corners projected with a known camera plus Gaussian noise.
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "calib/calib_camera.h"
#include "calib/target/aprilgrid.h"
#include "calib/target/target_observation.h"

namespace adugs::calib::synth {

inline std::vector<TargetObservation> syntheticViews(const CalibCamera& cam, const AprilGrid& grid,
                                                     int n_views, double noise_px,
                                                     unsigned seed = 7, double near_m = 0.7,
                                                     double far_m = 1.2) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const Eigen::Vector3d centre(grid.tag_cols * grid.pitch() / 2, grid.tag_rows * grid.pitch() / 2, 0);
  std::vector<TargetObservation> views;
  while (static_cast<int>(views.size()) < n_views) {
    // Camera on a sphere cap around the board normal, looking at a point near the centre.
    const double dist = near_m + (far_m - near_m) * (uni(rng) + 1) / 2;
    const double tilt = 0.6 * uni(rng), pan = 0.6 * uni(rng);
    const Eigen::Vector3d eye =
        centre + dist * Eigen::Vector3d(std::sin(pan), std::sin(tilt), std::cos(pan) * std::cos(tilt));
    const Eigen::Vector3d look = centre + Eigen::Vector3d(0.1 * uni(rng), 0.1 * uni(rng), 0);
    const Eigen::Vector3d z = (look - eye).normalized();
    const Eigen::Vector3d up = Eigen::AngleAxisd(0.4 * uni(rng), z) * Eigen::Vector3d(0, -1, 0);
    const Eigen::Vector3d x = up.cross(z).normalized() * -1.0;
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Matrix3d R_T_C;
    R_T_C << x, y, z;
    TargetObservation obs;
    obs.t_ns = static_cast<int64_t>(views.size()) * 50000000;
    for (int id = 0; id < grid.numTags(); ++id)
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p_T = grid.corner(id, k);
        const Eigen::Vector3d p_C = R_T_C.transpose() * (p_T - eye);
        Eigen::Vector2d uv;
        if (!cam.project(p_C, uv)) continue;
        if (uv.x() < 2 || uv.y() < 2 || uv.x() > cam.width - 3 || uv.y() > cam.height - 3) continue;
        uv += Eigen::Vector2d(noise(rng), noise(rng));
        obs.corners.push_back({id, k, uv, p_T});
      }
    if (obs.corners.size() >= 40) views.push_back(obs);
  }
  return views;
}

// A camera held almost still in front of the board (the weak case of issue 18: 30 views of
// one pose): the board seen nearly face-on (tilt_deg about a fixed axis) at distance_m, its
// centre offset in the camera frame by (offset_x, offset_y) metres, each view jittered by up to
// jitter_m and jitter_deg. Corners outside the image are dropped (the board may be cut).
inline std::vector<TargetObservation> nearStillViews(const CalibCamera& cam,
                                                     const AprilGrid& grid, int n_views,
                                                     double noise_px, unsigned seed,
                                                     double distance_m, double tilt_deg,
                                                     double jitter_m, double jitter_deg,
                                                     double offset_x = 0, double offset_y = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const Eigen::Vector3d centre(grid.tag_cols * grid.pitch() / 2, grid.tag_rows * grid.pitch() / 2, 0);
  const Eigen::Vector3d tilt_axis = Eigen::Vector3d(1, 0.6, 0).normalized();
  std::vector<TargetObservation> views;
  for (int k = 0; k < n_views; ++k) {
    // Board frame in the camera: z of the board towards the camera (R_C_T flips it), tilted.
    const Eigen::Vector3d jitter_axis(uni(rng), uni(rng), uni(rng));
    const Eigen::Matrix3d R_C_T =
        (Eigen::AngleAxisd(jitter_deg * M_PI / 180 * uni(rng), jitter_axis.normalized()) *
         Eigen::AngleAxisd(tilt_deg * M_PI / 180, tilt_axis) *
         Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Vector3d t_C_T =
        Eigen::Vector3d(offset_x, offset_y, distance_m) +
        jitter_m * Eigen::Vector3d(uni(rng), uni(rng), uni(rng)) - R_C_T * centre;
    TargetObservation obs;
    obs.t_ns = static_cast<int64_t>(k) * 50000000;
    for (int id = 0; id < grid.numTags(); ++id)
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector3d p_T = grid.corner(id, c);
        Eigen::Vector2d uv;
        if (!cam.project(R_C_T * p_T + t_C_T, uv)) continue;
        if (uv.x() < 2 || uv.y() < 2 || uv.x() > cam.width - 3 || uv.y() > cam.height - 3) continue;
        uv += Eigen::Vector2d(noise(rng), noise(rng));
        obs.corners.push_back({id, c, uv, p_T});
      }
    views.push_back(obs);
  }
  return views;
}

inline CalibCamera eurocLikeCamera() {
  CalibCamera c;
  c.width = 752;
  c.height = 480;
  c.model = DistortionModel::kRadialTangential;
  c.params = {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  return c;
}

inline CalibCamera fisheyeCamera() {
  CalibCamera c;
  c.width = 848;
  c.height = 800;
  c.model = DistortionModel::kEquidistant;
  c.params = {286.18, 286.39, 416.94, 403.27, -0.0029, 0.0379, -0.0367, 0.0066};
  return c;
}

// The wide-angle models with Basalt's EuRoC cam0 fits (basalt data/euroc_ds_calib.json,
// euroc_eucm_calib.json), and an omni camera of the same lens (on-axis focal ~460 px).
inline CalibCamera wideCamera(ProjectionModel projection) {
  CalibCamera c;
  c.width = 752;
  c.height = 480;
  c.projection = projection;
  c.model = DistortionModel::kNone;
  switch (projection) {
    case ProjectionModel::kDoubleSphere:
      c.params = {349.756, 348.725, 365.894, 249.330, 0, 0, 0, 0};
      c.projection_params = {-0.24096, 0.56700};
      break;
    case ProjectionModel::kExtendedUnified:
      c.params = {460.765, 459.405, 365.894, 249.335, 0, 0, 0, 0};
      c.projection_params = {0.59034, 1.12747};
      break;
    case ProjectionModel::kUnified:
      c.model = DistortionModel::kRadialTangential;
      c.params = {874.0, 871.5, 365.9, 249.3, -0.06, 0.02, 0.0005, -0.0003};
      c.projection_params = {0.9, 0};
      break;
    case ProjectionModel::kPinhole:
      return eurocLikeCamera();
  }
  return c;
}

}  // namespace adugs::calib::synth

#pragma once
// Synthetic AprilGrid views for the calibration tests: a camera looking at the grid from a
// spread of distances and angles, corners projected with a known camera plus Gaussian noise.
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "calib/aprilgrid.h"
#include "calib/camera_model.h"
#include "calib/target_observation.h"

namespace adugs::calib::synth {

inline std::vector<TargetObservation> syntheticViews(const PinholeCamera& cam, const AprilGrid& grid,
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

inline PinholeCamera eurocLikeCamera() {
  PinholeCamera c;
  c.width = 752;
  c.height = 480;
  c.model = DistortionModel::kRadialTangential;
  c.params = {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  return c;
}

inline PinholeCamera fisheyeCamera() {
  PinholeCamera c;
  c.width = 848;
  c.height = 800;
  c.model = DistortionModel::kEquidistant;
  c.params = {286.18, 286.39, 416.94, 403.27, -0.0029, 0.0379, -0.0367, 0.0066};
  return c;
}

}  // namespace adugs::calib::synth

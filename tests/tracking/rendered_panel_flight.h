#pragma once
// A rendered flight for the motion-cue tests: a textured wall seen by a moving camera and a
// textured panel moving in front of it, ray-traced per pixel (the exact images of a pinhole
// camera), so what the cue finds can be checked against where the panel really is.
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "data/camera_model.h"

namespace adugs::tracking {

inline const data::CameraModel kCamera(752, 480, 450, 450, 376, 240);

inline cv::Mat noiseTexture(int size, int seed) {
  cv::Mat t(size, size, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 2.0);
  cv::normalize(t, t, 0, 255, cv::NORM_MINMAX);
  return t;
}

// A wall (plane z = 5 m, 12 m wide) and a 1 m panel (plane z = panel_z, centred at panel_xy),
// both textured at 200 px per metre; the camera at `position` with rotation R_W_C (camera -> world).
struct Scene {
  cv::Mat wall = noiseTexture(2400, 1), panel = noiseTexture(200, 2);
  double panel_z = 3.0;

  cv::Mat render(const Eigen::Matrix3d& R_W_C, const Eigen::Vector3d& position, const Eigen::Vector2d& panel_xy,
                 cv::Mat* panel_mask) const {
    cv::Mat wall_x(480, 752, CV_32FC1), wall_y(480, 752, CV_32FC1), panel_x(480, 752, CV_32FC1),
        panel_y(480, 752, CV_32FC1);
    *panel_mask = cv::Mat::zeros(480, 752, CV_8UC1);
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 752; ++u) {
        const Eigen::Vector3d ray = R_W_C * kCamera.unproject(Eigen::Vector2d(u, v));
        const Eigen::Vector3d on_panel = position + (panel_z - position.z()) / ray.z() * ray;
        const Eigen::Vector2d p = (on_panel.head<2>() - panel_xy) * 200 + Eigen::Vector2d(100, 100);
        panel_x.at<float>(v, u) = static_cast<float>(p.x());
        panel_y.at<float>(v, u) = static_cast<float>(p.y());
        if (p.x() >= 0 && p.y() >= 0 && p.x() < 199 && p.y() < 199) panel_mask->at<uint8_t>(v, u) = 255;
        const Eigen::Vector3d on_wall = position + (5.0 - position.z()) / ray.z() * ray;
        const Eigen::Vector2d w = on_wall.head<2>() * 200 + Eigen::Vector2d(1200, 1200);
        wall_x.at<float>(v, u) = static_cast<float>(w.x());
        wall_y.at<float>(v, u) = static_cast<float>(w.y());
      }
    cv::Mat image, panels;
    cv::remap(wall, image, wall_x, wall_y, cv::INTER_LINEAR);
    cv::remap(panel, panels, panel_x, panel_y, cv::INTER_LINEAR);
    panels.copyTo(image, *panel_mask);
    return image;
  }
};

// Frame k of a flight at 20 frames per second: the camera translates `step` per frame and turns
// `yaw_deg` per frame about its y axis, from (-0.3, 0, 0); the panel moves `panel_step` per frame
// from (0.2, -0.6). R_Ccur_Cprev is the true rotation since frame k - 1 (a perfect gyro), v_C the
// camera's true velocity in its own frame.
struct PanelFlightFrame {
  cv::Mat image, panel_mask;
  Eigen::Matrix3d R_Ccur_Cprev, R_W_C;
  Eigen::Vector3d v_C;
};
constexpr double kFlightFps = 20;

inline PanelFlightFrame panelFlightFrame(const Scene& scene, const Eigen::Vector3d& step, double yaw_deg,
                                         const Eigen::Vector2d& panel_step, int k) {
  const auto R_W_C = [&](int i) {
    return Eigen::AngleAxisd(yaw_deg * i * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  };
  PanelFlightFrame f;
  f.image = scene.render(R_W_C(k), Eigen::Vector3d(-0.3, 0, 0) + k * step,
                         Eigen::Vector2d(0.2, -0.6) + k * panel_step, &f.panel_mask);
  f.R_Ccur_Cprev = R_W_C(k).transpose() * R_W_C(std::max(0, k - 1));
  f.v_C = R_W_C(k).transpose() * step * kFlightFps;
  f.R_W_C = R_W_C(k);
  return f;
}

}  // namespace adugs::tracking

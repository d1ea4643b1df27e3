// The class-free motion cue on rendered frames: a textured wall seen by a moving camera and a
// textured panel moving in front of it, ray-traced per pixel (the exact images of a pinhole
// camera), so the boxes can be checked against where the panel really is.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "tracking/detect/motion_cue.h"

namespace adugs::tracking {
namespace {

const data::CameraModel kCamera(752, 480, 450, 450, 376, 240);

cv::Mat noiseTexture(int size, int seed) {
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

struct Outcome {
  int frames_with_a_box_on_the_panel = 0;
  int frames_with_a_box_off_the_panel = 0;
  int translating_frames = 0;
  int frames = 0;
};

// The camera translates `step` per frame and turns `yaw_deg` per frame about its y axis; the
// panel moves `panel_step` per frame. The motion cue gets the true rotation (a perfect gyro).
// With know_velocity the cue gets the camera's true velocity (the estimator's, in the pipeline);
// else it fits the translation direction itself.
Outcome run(const Eigen::Vector3d& step, double yaw_deg, const Eigen::Vector2d& panel_step, bool know_velocity = false,
            int frames = 12) {
  const Scene scene;
  MotionCue cue(kCamera);
  Outcome o;
  Eigen::Matrix3d previous_R = Eigen::Matrix3d::Identity();
  for (int k = 0; k < frames; ++k) {
    const Eigen::Matrix3d R_W_C = Eigen::AngleAxisd(yaw_deg * k * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d position = Eigen::Vector3d(-0.3, 0, 0) + k * step;
    const Eigen::Vector2d panel_xy = Eigen::Vector2d(0.2, -0.6) + k * panel_step;
    cv::Mat panel_mask;
    const cv::Mat image = scene.render(R_W_C, position, panel_xy, &panel_mask);
    const Eigen::Matrix3d R_Ccur_Cprev = R_W_C.transpose() * previous_R;
    previous_R = R_W_C;
    std::optional<Eigen::Vector3d> v_C;
    if (know_velocity) v_C = R_W_C.transpose() * step * 20.0;  // 20 frames per second
    const std::vector<Detection> boxes = cue.detect(image, R_Ccur_Cprev, v_C);
    if (k < 3) continue;  // a point moves after 2 of its last 3 frames: from the third frame on
    ++o.frames;
    o.translating_frames += cue.translating();
    // On the panel: a box holding most of the panel's pixels, at least 40 % of it panel (the
    // box reaches past the outermost points by design). Off: a box nearly all wall.
    bool on = false, off = false;
    const double panel_pixels = std::max(1, cv::countNonZero(panel_mask));
    for (const Detection& d : boxes) {
      EXPECT_EQ(d.class_id, kMovingClass);
      const cv::Rect r = cv::Rect(d.box.rect()) & cv::Rect(0, 0, 752, 480);
      const double covered = cv::countNonZero(panel_mask(r));
      const double precision = covered / std::max(1.0, static_cast<double>(r.area()));
      if (covered / panel_pixels >= 0.7 && precision >= 0.4) on = true;
      if (precision < 0.1) off = true;
    }
    o.frames_with_a_box_on_the_panel += on;
    o.frames_with_a_box_off_the_panel += off;
  }
  return o;
}

TEST(MotionCue, PanelMovingAcrossTheEpipolarLinesOfATranslatingCameraIsBoxed) {
  // Sideways camera (4 cm per frame, parallax ~3.6 px on the wall) turning 0.3 degrees per frame;
  // the panel moves up 2 cm per frame, across the horizontal epipolar lines.
  const Outcome o = run({0.04, 0, 0}, 0.3, {0, 0.02});
  EXPECT_EQ(o.translating_frames, o.frames) << "the wall's parallax was not seen as translation";
  EXPECT_GE(o.frames_with_a_box_on_the_panel, o.frames - 1);
  EXPECT_EQ(o.frames_with_a_box_off_the_panel, 0);
}

TEST(MotionCue, PanelOvertakingTheCameraAlongItsEpipolarLinesIsBoxed) {
  // The panel goes the camera's way at 2.5 times its speed: its image motion lies on its
  // epipolar lines but runs towards the direction of travel, which no static point does.
  const Outcome o = run({0.04, 0, 0}, 0.3, {0.1, 0});
  EXPECT_EQ(o.translating_frames, o.frames);
  EXPECT_GE(o.frames_with_a_box_on_the_panel, o.frames - 1);
  EXPECT_EQ(o.frames_with_a_box_off_the_panel, 0);
}

TEST(MotionCue, StaticPanelOfATranslatingCameraIsNotBoxed) {
  // The same flight with the panel still: it has more parallax than the wall but is static.
  const Outcome o = run({0.04, 0, 0}, 0.3, {0, 0});
  EXPECT_EQ(o.frames_with_a_box_on_the_panel, 0);
  EXPECT_EQ(o.frames_with_a_box_off_the_panel, 0);
}

TEST(MotionCue, PanelSeenByARotatingCameraIsBoxedWhenItMoves) {
  // A camera turning 1 degree per frame on the spot: the gyro explains all the wall's motion.
  // With and without the velocity: fitted, a translation could line up with the panel (the
  // wall has no parallax); it is not taken as it explains too few points more.
  for (const bool know_velocity : {false, true}) {
    const Outcome moving = run({0, 0, 0}, 1.0, {0.02, 0.0}, know_velocity);
    EXPECT_EQ(moving.translating_frames, 0) << know_velocity;
    EXPECT_GE(moving.frames_with_a_box_on_the_panel, moving.frames - 1) << know_velocity;
    EXPECT_EQ(moving.frames_with_a_box_off_the_panel, 0) << know_velocity;
    const Outcome still = run({0, 0, 0}, 1.0, {0, 0}, know_velocity);
    EXPECT_EQ(still.frames_with_a_box_on_the_panel + still.frames_with_a_box_off_the_panel, 0) << know_velocity;
  }
}

TEST(MotionCue, KnownVelocityGivesTheDirectionOfTravel) {
  // The flights of the first two tests with the camera's velocity given instead of fitted.
  const Outcome across = run({0.04, 0, 0}, 0.3, {0, 0.02}, true);
  EXPECT_EQ(across.translating_frames, across.frames);
  EXPECT_GE(across.frames_with_a_box_on_the_panel, across.frames - 1);
  EXPECT_EQ(across.frames_with_a_box_off_the_panel, 0);
  const Outcome overtaking = run({0.04, 0, 0}, 0.3, {0.1, 0}, true);
  EXPECT_GE(overtaking.frames_with_a_box_on_the_panel, overtaking.frames - 1);
  EXPECT_EQ(overtaking.frames_with_a_box_off_the_panel, 0);
  const Outcome still = run({0.04, 0, 0}, 0.3, {0, 0}, true);
  EXPECT_EQ(still.frames_with_a_box_on_the_panel + still.frames_with_a_box_off_the_panel, 0);
}

TEST(MotionCue, AKnownVelocityIsTranslationEvenWithoutParallax) {
  // A slow sideways camera (1 cm per frame: under 1 px of parallax on the wall) with its velocity
  // known: the translating model is used on every frame; fitted, "rotation only" explains the
  // frames as well and is kept. Nothing is boxed either way.
  const Outcome known = run({0.01, 0, 0}, 0.3, {0, 0}, true);
  EXPECT_EQ(known.translating_frames, known.frames);
  EXPECT_EQ(known.frames_with_a_box_on_the_panel + known.frames_with_a_box_off_the_panel, 0);
  const Outcome fitted = run({0.01, 0, 0}, 0.3, {0, 0}, false);
  EXPECT_EQ(fitted.translating_frames, 0);
}

// The panel moves 5 cm per frame across the epipolar lines (7.5 px per frame at 3 m): its points
// pass strong_threshold_px from their first residual, so the panel is boxed in the second frame;
// with the 2-of-3 vote alone (strong threshold out of reach) not before the third.
TEST(MotionCue, ClearMotionCountsFromAPointsFirstResidual) {
  const Scene scene;
  for (const bool strong : {true, false}) {
    MotionCueOptions options;
    if (!strong) options.strong_threshold_px = 1000;
    MotionCue cue(kCamera, options);
    std::vector<size_t> boxes_per_frame;
    for (int k = 0; k < 3; ++k) {
      cv::Mat panel_mask;
      const cv::Mat image = scene.render(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.3, 0, 0),
                                         Eigen::Vector2d(0.2, -0.6 + 0.05 * k), &panel_mask);
      boxes_per_frame.push_back(cue.detect(image, Eigen::Matrix3d::Identity()).size());
      if (k == 2) {
        // Still points: tracked twice with no motion (the wall); moving ones are never still.
        int still_on_panel = 0, still_on_wall = 0;
        for (const MotionCuePoint& p : cue.points()) {
          EXPECT_FALSE(p.still && p.moving);
          const bool on_panel = panel_mask.at<uint8_t>(cv::Point(p.pixel)) > 0;
          (on_panel ? still_on_panel : still_on_wall) += p.still;
        }
        EXPECT_EQ(still_on_panel, 0);
        EXPECT_GT(still_on_wall, 100);
      }
    }
    EXPECT_EQ(boxes_per_frame[0], 0u);
    EXPECT_EQ(boxes_per_frame[1], strong ? 1u : 0u) << strong;
    EXPECT_EQ(boxes_per_frame[2], 1u) << strong;
  }
}

TEST(MotionCue, BadInputsAreRejected) {
  MotionCue cue(kCamera);
  EXPECT_THROW(cue.detect(cv::Mat(480, 752, CV_32FC1, cv::Scalar(0)), Eigen::Matrix3d::Identity()), std::invalid_argument);
  EXPECT_THROW(cue.detect(cv::Mat(600, 800, CV_8UC1, cv::Scalar(0)), Eigen::Matrix3d::Identity()), std::invalid_argument);
  MotionCueOptions o;
  o.min_points = 0;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  // A blank frame has no corners: no points, no boxes, no failure.
  const cv::Mat blank(480, 752, CV_8UC1, cv::Scalar(90));
  EXPECT_TRUE(cue.detect(blank, Eigen::Matrix3d::Identity()).empty());
  EXPECT_TRUE(cue.detect(blank, Eigen::Matrix3d::Identity()).empty());
  EXPECT_TRUE(cue.points().empty());
}

}  // namespace
}  // namespace adugs::tracking

// The class-free motion cue on rendered frames (tests/tracking/rendered_panel_flight.h), so the
// boxes can be checked against where the panel really is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "tests/tracking/rendered_panel_flight.h"
#include "tracking/detect/motion_cue.h"

namespace adugs::tracking {
namespace {

struct Outcome {
  int frames_with_a_box_on_the_panel = 0;
  int frames_with_a_box_off_the_panel = 0;
  int translating_frames = 0;
  int frames = 0;
  std::vector<double> rolls;  // MotionCue::roll() per frame from the third on
  int moving_points_off_the_panel = 0;  // over those frames, farther than 20 px from the panel
};

// The flight of panelFlightFrame. With know_velocity the cue gets the camera's true velocity (the
// estimator's, in the pipeline); else it fits the translation direction itself. The rotation the
// cue is given is the true one followed by gyro_error (a perfect gyro by default).
Outcome run(const Eigen::Vector3d& step, double yaw_deg, const Eigen::Vector2d& panel_step, bool know_velocity = false,
            int frames = 12, const Eigen::Matrix3d& gyro_error = Eigen::Matrix3d::Identity()) {
  const Scene scene;
  MotionCue cue(kCamera);
  Outcome o;
  for (int k = 0; k < frames; ++k) {
    const PanelFlightFrame f = panelFlightFrame(scene, step, yaw_deg, panel_step, k);
    const cv::Mat& panel_mask = f.panel_mask;
    std::optional<Eigen::Vector3d> v_C;
    if (know_velocity) v_C = f.v_C;
    const std::vector<Detection> boxes = cue.detect(f.image, gyro_error * f.R_Ccur_Cprev, v_C);
    if (k < 3) continue;  // a point moves after 2 of its last 3 frames: from the third frame on
    ++o.frames;
    o.rolls.push_back(cue.roll());
    cv::Mat near_panel;
    cv::dilate(panel_mask, near_panel, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(41, 41)));
    for (const MotionCuePoint& p : cue.points()) o.moving_points_off_the_panel += p.moving && near_panel.at<uint8_t>(cv::Point(p.pixel)) == 0;
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

// The gyro's rotation off by 0.5 degrees per frame about the optical axis (0.17 rad/s at 20 Hz:
// twice EuRoC V1_01's 0.077 rad/s before the estimator has found it, so that the edges' points
// move by 2-2.8 px against it, well beyond threshold_px; the centre's do not move). Without the
// estimator's velocity the cue finds that turn from the points: no wall point moves, the panel
// moving across the wall is boxed. With a velocity (whose estimator would know the bias) the
// rotation is taken as given and the edges' points move: what the fit prevents.
TEST(MotionCue, AGyroBiasAboutTheOpticalAxisIsFoundFromThePointsBeforeTheVelocityIsKnown) {
  const double bias_rad = 0.5 * M_PI / 180;
  const Eigen::Matrix3d error = Eigen::AngleAxisd(bias_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Outcome still = run({0, 0, 0}, 0.3, {0, 0}, false, 12, error);
  EXPECT_EQ(still.frames_with_a_box_on_the_panel + still.frames_with_a_box_off_the_panel, 0);
  EXPECT_EQ(still.moving_points_off_the_panel, 0);
  for (const double roll : still.rolls) EXPECT_NEAR(roll, -bias_rad, 0.05 * bias_rad);
  const Outcome moving = run({0, 0, 0}, 0.3, {0, 0.02}, false, 12, error);
  EXPECT_GE(moving.frames_with_a_box_on_the_panel, moving.frames - 1);
  EXPECT_EQ(moving.frames_with_a_box_off_the_panel, 0);
  // Sideways at 4 cm per frame, the translation fitted: the turn is found beside it (the parallax
  // of the turned wall, larger on its nearer side, adds a little turn of its own).
  const Outcome translating = run({0.04, 0, 0}, 0.3, {0, 0}, false, 12, error);
  EXPECT_EQ(translating.frames_with_a_box_on_the_panel + translating.frames_with_a_box_off_the_panel, 0);
  EXPECT_EQ(translating.moving_points_off_the_panel, 0);
  for (const double roll : translating.rolls) EXPECT_NEAR(roll, -bias_rad, 0.15 * bias_rad);
  // The same with a perfect gyro: the translation explains the frames, no turn is taken.
  for (const double roll : run({0.04, 0, 0}, 0.3, {0, 0}).rolls) EXPECT_EQ(roll, 0);
  const Outcome given = run({0, 0, 0}, 0.3, {0, 0}, true, 12, error);
  for (const double roll : given.rolls) EXPECT_EQ(roll, 0);
  EXPECT_GT(given.moving_points_off_the_panel, 10 * given.frames) << "the biased rotation was expected to move the edges' points";
  // A perfect gyro: nothing to find. A bias a tenth as large (0.1 px on the edges) is within
  // KLT's noise and left alone.
  for (const double roll : run({0, 0, 0}, 0.3, {0, 0}).rolls) EXPECT_EQ(roll, 0);
  const Eigen::Matrix3d small = Eigen::AngleAxisd(bias_rad / 10, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const double roll : run({0, 0, 0}, 0.3, {0, 0}, false, 12, small).rolls) EXPECT_EQ(roll, 0);
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

// With the velocity and the frame interval the translation's length is known, and a static
// point's slide along its epipolar line gives its range: the wall is 5 m deep, the panel 3 m.
TEST(MotionCue, KnownTranslationGivesTheRangesOfStaticPoints) {
  const Scene scene;
  MotionCue cue(kCamera);
  std::vector<double> wall_ratios, panel_ratios;
  for (int k = 0; k < 6; ++k) {
    const PanelFlightFrame f = panelFlightFrame(scene, {0.04, 0, 0}, 0.3, {0, 0}, k);
    cue.detect(f.image, f.R_Ccur_Cprev, f.v_C, 1 / kFlightFps);
    // Points within 8 px of the panel's edge track both surfaces: left out.
    cv::Mat panel, near_panel;
    const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(17, 17));
    cv::erode(f.panel_mask, panel, disc);
    cv::dilate(f.panel_mask, near_panel, disc);
    for (const MotionCuePoint& p : cue.points()) {
      if (p.slide_at_1m_px <= 0) continue;  // new in this frame
      const bool on_panel = panel.at<uint8_t>(cv::Point(p.pixel)) > 0;
      if (!on_panel && near_panel.at<uint8_t>(cv::Point(p.pixel)) > 0) continue;
      ASSERT_GT(p.slide_px, 0);
      const Eigen::Vector3d ray = (f.R_W_C * kCamera.unproject(Eigen::Vector2d(p.pixel.x, p.pixel.y))).normalized();
      const double depth = p.slide_at_1m_px / p.slide_px * ray.z();  // the camera stays at z = 0
      (on_panel ? panel_ratios : wall_ratios).push_back(depth / (on_panel ? 3.0 : 5.0));
    }
  }
  ASSERT_GT(wall_ratios.size(), 500u);
  ASSERT_GT(panel_ratios.size(), 50u);
  for (std::vector<double>* ratios : {&wall_ratios, &panel_ratios}) {
    std::sort(ratios->begin(), ratios->end());
    EXPECT_NEAR((*ratios)[ratios->size() / 2], 1.0, 0.03);
    EXPECT_GT((*ratios)[ratios->size() / 10], 0.95);
    EXPECT_LT((*ratios)[ratios->size() * 9 / 10], 1.05);
  }
  // Without the frame interval (or the velocity) no slides.
  MotionCue unknown(kCamera);
  for (int k = 0; k < 3; ++k) {
    const PanelFlightFrame f = panelFlightFrame(scene, {0.04, 0, 0}, 0.3, {0, 0}, k);
    unknown.detect(f.image, f.R_Ccur_Cprev, f.v_C);
    for (const MotionCuePoint& p : unknown.points()) EXPECT_EQ(p.slide_at_1m_px, 0);
  }
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

// Still points are tracked on still_pyramid_levels only; one that jumps beyond their reach (the
// camera, at rest for four frames, steps 0.17 m sideways: the wall, 5 m away, moves 15 px) is
// tracked again on all klt_pyramid_levels. Without that, two thirds of the wall's points are lost
// (279 of 417 kept) and a dozen mistracked ones are taken for movers.
TEST(MotionCue, StillPointsBeyondTheReachOfTheirLevelsAreTrackedOnAll) {
  const Scene scene;
  MotionCueOptions options;
  options.still_pyramid_levels = 0;  // reach ~5 px
  MotionCue cue(kCamera, options);
  cv::Mat panel_mask;
  int still_before = 0;
  for (int k = 0; k < 5; ++k) {
    const double x = k < 4 ? -0.3 : -0.3 + 15.0 * 5 / 450;
    const cv::Mat image = scene.render(Eigen::Matrix3d::Identity(), Eigen::Vector3d(x, 0, 0), Eigen::Vector2d(0.2, -0.6), &panel_mask);
    cue.detect(image, Eigen::Matrix3d::Identity());
    if (k == 3)
      for (const MotionCuePoint& p : cue.points()) still_before += p.still;
  }
  // After the step: the wall's points kept their history (still again), none was boxed.
  cv::Mat near_panel;
  cv::dilate(panel_mask, near_panel, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(41, 41)));
  int still_on_wall = 0, moving = 0;
  for (const MotionCuePoint& p : cue.points()) {
    moving += p.moving;
    if (near_panel.at<uint8_t>(cv::Point(p.pixel)) == 0) still_on_wall += p.still;
  }
  ASSERT_GT(still_before, 400);
  EXPECT_GT(still_on_wall, still_before * 6 / 10);
  EXPECT_LT(moving, 10);
}

// A fast mover (the panel 0.2 m per frame at 3 m: ~30 px per frame, a car passing near the
// camera) is beyond KLT's reach with two pyramid levels (~22 px for an 11 px window): its points
// are lost every frame and never get a residual. Three levels (the default) follow it.
TEST(MotionCue, FastMoverIsFollowedWithThreePyramidLevels) {
  const Scene scene;
  int boxed[2] = {0, 0}, frames = 0;
  for (const int levels : {2, 3}) {
    MotionCueOptions options;
    options.klt_pyramid_levels = levels;
    MotionCue cue(kCamera, options);
    frames = 0;
    for (int k = 0; k < 9; ++k) {
      cv::Mat panel_mask;
      const cv::Mat image = scene.render(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.3, 0, 0),
                                         Eigen::Vector2d(-1.6 + 0.2 * k, -0.2), &panel_mask);
      const std::vector<Detection> boxes = cue.detect(image, Eigen::Matrix3d::Identity());
      if (k < 3) continue;
      ++frames;
      const double panel_pixels = std::max(1, cv::countNonZero(panel_mask));
      for (const Detection& d : boxes) {
        const cv::Rect r = cv::Rect(d.box.rect()) & cv::Rect(0, 0, 752, 480);
        if (cv::countNonZero(panel_mask(r)) / panel_pixels >= 0.5) {
          ++boxed[levels - 2];
          break;
        }
      }
    }
  }
  EXPECT_EQ(MotionCueOptions{}.klt_pyramid_levels, 3);
  EXPECT_LE(boxed[0], frames / 2) << "two levels were expected to lose the panel";
  EXPECT_GE(boxed[1], frames - 1);
}

// Hand-worked structure tensors [xx xy; xy yy] of gradient windows, in the cue's CV_16SC2 form.
TEST(MotionCue, CornerRatioIsTheStructureTensorsSmallerOverLargerEigenvalue) {
  const auto window = [](const std::vector<std::pair<cv::Point, cv::Vec2s>>& gradients) {
    cv::Mat g(21, 21, CV_16SC2, cv::Scalar(0, 0));
    for (const auto& [at, value] : gradients) g.at<cv::Vec2s>(at) = value;
    return g;
  };
  const cv::Point2f centre(10, 10);
  // A vertical edge: every gradient along x, [xx 0; 0 0], eigenvalues xx and 0.
  EXPECT_DOUBLE_EQ(cornerRatio(window({{{10, 8}, {50, 0}}, {{10, 9}, {50, 0}}, {{10, 11}, {50, 0}}}), centre, 3), 0.0);
  // A diagonal edge: gradients (g, g), [a a; a a], eigenvalues 2a and 0.
  EXPECT_NEAR(cornerRatio(window({{{9, 9}, {30, 30}}, {{10, 10}, {30, 30}}, {{11, 11}, {30, 30}}}), centre, 3), 0.0, 1e-12);
  // A corner: one gradient along x, one along y, equal: [a 0; 0 a], ratio 1.
  EXPECT_DOUBLE_EQ(cornerRatio(window({{{10, 9}, {40, 0}}, {{9, 10}, {0, 40}}}), centre, 3), 1.0);
  // (2, 0) and (0, 1): [4 0; 0 1], ratio 1/4. (2, 0) and (1, 1): [5 1; 1 1], eigenvalues 3 -+ sqrt(5).
  EXPECT_DOUBLE_EQ(cornerRatio(window({{{10, 9}, {2, 0}}, {{9, 10}, {0, 1}}}), centre, 3), 0.25);
  EXPECT_NEAR(cornerRatio(window({{{10, 9}, {2, 0}}, {{9, 10}, {1, 1}}}), centre, 3), (3 - std::sqrt(5.0)) / (3 + std::sqrt(5.0)), 1e-12);
  // Flat: no gradient at all; and a gradient outside the window does not count.
  EXPECT_DOUBLE_EQ(cornerRatio(window({}), centre, 3), 0.0);
  EXPECT_DOUBLE_EQ(cornerRatio(window({{{10, 9}, {40, 0}}, {{9, 14}, {0, 40}}}), centre, 3), 0.0);
  // A window over the image's edge is clipped to it.
  EXPECT_DOUBLE_EQ(cornerRatio(window({{{0, 1}, {40, 0}}, {{1, 0}, {0, 40}}}), cv::Point2f(0, 0), 3), 1.0);
}

TEST(MotionCue, BadInputsAreRejected) {
  MotionCue cue(kCamera);
  EXPECT_THROW(cue.detect(cv::Mat(480, 752, CV_32FC1, cv::Scalar(0)), Eigen::Matrix3d::Identity()), std::invalid_argument);
  EXPECT_THROW(cue.detect(cv::Mat(600, 800, CV_8UC1, cv::Scalar(0)), Eigen::Matrix3d::Identity()), std::invalid_argument);
  MotionCueOptions o;
  o.min_points = 0;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  o = MotionCueOptions{};
  o.klt_pyramid_levels = -1;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  o = MotionCueOptions{};
  o.still_pyramid_levels = -1;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  o = MotionCueOptions{};
  o.min_corner_points = -1;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  o = MotionCueOptions{};
  o.corner_ratio = 1.5;
  EXPECT_THROW(MotionCue(kCamera, o), std::invalid_argument);
  EXPECT_THROW(cornerRatio(cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)), cv::Point2f(10, 10), 5), std::invalid_argument);
  // A blank frame has no corners: no points, no boxes, no failure.
  const cv::Mat blank(480, 752, CV_8UC1, cv::Scalar(90));
  EXPECT_TRUE(cue.detect(blank, Eigen::Matrix3d::Identity()).empty());
  EXPECT_TRUE(cue.detect(blank, Eigen::Matrix3d::Identity()).empty());
  EXPECT_TRUE(cue.points().empty());
}

}  // namespace
}  // namespace adugs::tracking

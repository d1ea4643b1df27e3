#pragma once
// A class-free detector of moving objects: image points whose motion since the previous frame
// disagrees with the camera's own motion, grouped into boxes that prompt the same SORT and box
// segmenter as the object detector's boxes (tracking/dynamic_masker.h). Nothing is learnt, so any
// object that moves is found, of whatever class; an object that stands still is not.
// Per frame:
//   1. points: the previous frame's points tracked by pyramidal KLT from where the gyro's rotation
//      and their last drift put them (kept when the backward track returns within 1 px; a still
//      point on fewer levels, again on all when lost so), topped up with the strongest corner (minimum eigenvalue, at
//      half resolution: a quarter of the cost) of every cell_px grid cell that has no point, so that every textured part of the image, a small
//      object's included, has points (the strongest corners of the whole image crowd into the
//      most contrasted texture);
//   2. the camera's rotation since the previous frame (the gyro's) is removed: each previous ray
//      is rotated into this camera, so a static point far away stays put; without the
//      estimator's velocity (before its first state, so with the gyro's bias unknown) also the
//      turn about the optical axis the points show (fitRoll), when the static scene's model fits
//      them better with it taken out (turnExplainsMore);
//   3. the static scene's model, one of two: rotation only (a static point stays where the
//      rotation puts it: its residual is its compensated motion, as an angle in pixels on the
//      optical axis), or a translating camera (static points slide along their epipolar lines:
//      the translation direction by RANSAC over two-point samples, as the epipolar plane of a
//      point contains the translation; the residual is the angle to that plane, in pixels; a point
//      that slides along its line towards the direction of travel, which static points never do,
//      has its whole compensated motion as residual). The translating model is taken when it
//      explains translation_min_gain of the points more than the rotation-only one. With the
//      estimator's velocity the direction is known, not fitted: the fit can line up with a large
//      moving object when the static scene has no parallax;
//   4. a point moves when its residual is above threshold_px in at least 2 of its last 3 frames,
//      or above strong_threshold_px in this one (points on a walking person or an object's edge
//      rarely live three frames: a young point with clear motion counts at once);
//      moving points closer than group_radius_px form a group; a group of min_points or more, of
//      which min_corner_points are corners (cornerRatio at least corner_ratio), is a box (their
//      bounding box, widened by box_margin on each side), score 1, class kMovingClass.
// What it cannot see: motion along the point's epipolar line that a static point could have at
// some depth (an object coming towards a forward-moving camera, or going its way more slowly than
// it: both look like static points at another depth; telling them apart needs depth, e.g. where
// the object touches the ground), and objects without trackable texture.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "data/camera_model.h"
#include "tracking/detect/detector.h"

namespace adugs::tracking {

// The class id of the motion cue's boxes (no detector class; SORT keeps them apart).
constexpr int kMovingClass = -1;

struct MotionCueOptions {
  int cell_px = 24;               // one point per grid cell of this side
  // Side of KLT's window: its cost grows with the area (15 -> 11: half the KLT's time, the
  // masks' recall unchanged over 9 sequences; doc/results.md, "The motion cue's cost").
  int klt_window_px = 11;
  // Pyramid levels above the image for KLT: each doubles the motion it can follow (about
  // klt_window_px / 2 * 2^levels px per frame). 2 -> 3: a car passing near the camera moves
  // ~30 px per frame and lost its points every frame; moving-pixel recall 0.61-0.75 -> 0.73-0.82
  // on the moving-box flights, street cars +0.03-0.11 over 8 seeds, the wall unchanged
  // (doc/results.md, "The cue's KLT reach").
  int klt_pyramid_levels = 3;
  // Levels for a still point (MotionCuePoint::still), started where the rotation and its last
  // drift put it: the static scene, most of the points, needs little reach (3 -> 2: the masked
  // run's wall 0.95x on a moving-box flight, recall and precision the same; doc/results.md,
  // "Still points on fewer levels"). One lost that way is tracked again on klt_pyramid_levels.
  int still_pyramid_levels = 2;
  // Of the image's strongest corner: weaker cells get no point. Low: the plain textures of
  // vehicles and walls are where movers lose their points (0.001 -> 0.0001: moving-pixel recall
  // 0.50 -> 0.67 over 9 simulated sequences, street 0.33 -> 0.61; doc/results.md).
  double corner_quality = 0.0001;
  double threshold_px = 1.5;      // residual above which a point moves in a frame
  double strong_threshold_px = 4.5;  // residual above which one frame is enough
  double translation_min_gain = 0.1;  // of the points (at least 5): see 3. above
  double min_speed = 0.02;            // m/s: a known velocity below it is no translation
  int ransac_iterations = 200;
  double group_radius_px = 40;    // moving points this close belong to one object
  // Moving points that make a box. 3 -> 4: the false boxes of a scene with nothing moving cover
  // half as much (masked share 0.50 -> 0.18 % room, 0.54 -> 0.27 % street), mask precision
  // 0.58 -> 0.62 room, recall 0.67 -> 0.66 (doc/results.md, "Fewer false boxes"); 5 lost the
  // room's small movers (ATE 0.85x -> 1.37x the exact masks').
  int min_points = 4;
  // Of a group's moving points, how many must be corners: a point on a straight edge slides along
  // it, and its track is wrong by that slide. Where nothing moves the false groups are such points
  // (a static scene's false mask, 16 sequences at level `none`: 0.01-1.0 % of the image on 15
  // of them -> 0 on all but 3 rooms, every street's run the unmasked one; moving-pixel recall
  // 0.693 -> 0.686 over 9 sequences; doc/results.md, "Two corners make a box"). A mover's group
  // has corners among its points, its silhouette's edge points are about half of them.
  int min_corner_points = 2;
  double corner_ratio = 0.1;      // smallest / largest eigenvalue of the gradients' structure tensor
  double box_margin = 0.1;        // of the box's width / height, on each side
};

// How much the window (2 radius + 1 pixels square) around pixel is a corner: the smaller
// eigenvalue over the larger of its gradients' structure tensor. 0 on a straight edge (the
// gradients all point one way) and where the window is flat, 1 where they spread evenly.
// gradients: CV_16SC2 (dI/dx, dI/dy), as cv::buildOpticalFlowPyramid's derivative levels; the
// window is clipped to the image.
double cornerRatio(const cv::Mat& gradients, const cv::Point2f& pixel, int radius);

// One tracked point and whether it moved, for the overlay and the tests.
struct MotionCuePoint {
  cv::Point2f pixel;
  bool moving = false;
  bool still = false;      // tracked over the last 2 frames with residuals below threshold_px in both
  double residual_px = 0;  // this frame's (0 for a point new in it)
  // With a known translation d since the previous frame (velocity and frame interval), else 0:
  // the point's slide along its epipolar line, positive the way static points slide, and the
  // slide a static point 1 m away would have (f |d x ray|). A static point's range is
  // slide_at_1m_px / slide_px metres: what tracking/object_motion.h checks against an object's size.
  double slide_px = 0;
  double slide_at_1m_px = 0;
};

class MotionCue {
 public:
  // camera: rays from pixels and the focal length residuals are measured with.
  explicit MotionCue(const data::CameraModel& camera, const MotionCueOptions& options = {});

  // grey: CV_8UC1 (CV_8UC3 is converted), the camera's image size (else std::invalid_argument). R_Ccur_Cprev: the camera's
  // rotation since the previous frame (a ray of the previous camera -> this one's); the identity
  // for a camera that did not rotate or has no gyro. v_C: the camera's velocity in its own frame
  // when known (the estimator's, in m/s): its direction is the translation's, no RANSAC needed;
  // below min_speed the frame is rotation-only. dt_s: the time since the previous frame; with v_C
  // it gives the translation's length, so the points' slides (MotionCuePoint). The first frame
  // gives no boxes.
  std::vector<Detection> detect(const cv::Mat& image, const Eigen::Matrix3d& R_Ccur_Cprev,
                                const std::optional<Eigen::Vector3d>& v_C = std::nullopt, double dt_s = 0);

  const std::vector<MotionCuePoint>& points() const { return points_; }
  // Whether the last frame's static model was the translating one (epipolar) or rotation only.
  bool translating() const { return translating_; }
  // The turn about the optical axis found on the last frame beyond the rotation given (radians;
  // 0 with a known velocity, whose estimator knows the gyro's bias): fitRoll.
  double roll() const { return roll_rad_; }

 private:
  struct Track {
    cv::Point2f pixel;
    cv::Point2f drift;    // last frame's motion beyond where the rotation put it (px)
    uint8_t history = 0;  // bit k: moved k frames ago (bit 0: this frame)
    uint8_t age = 0;      // frames tracked (saturates)
  };
  // Per point of `tracks_` (after tracking into this frame): residual in pixels.
  std::vector<double> residuals(const std::vector<Eigen::Vector3d>& previous_rays,
                                const std::vector<Eigen::Vector3d>& rays, const std::optional<Eigen::Vector3d>& v_C);
  // Before the estimator's first state the gyro's bias is unknown (the rotation given is the raw
  // gyro's). A bias about x or y moves every point alike, which the fitted translation absorbs;
  // one about the optical axis turns the image about its centre, which no translation does, and
  // moves the edges' points by their radius times bias times dt: EuRoC V1_01's 0.077 rad/s is
  // 1.4 px per frame on the edges of its 752 px image at 20 Hz, and the cue boxed them (2 % of
  // the image masked on a static room). This is that turn, in radians, from the points: the
  // weighted median of each point's, refined by least squares on those it explains; 0 when it
  // moves no point by 0.3 px (KLT's noise).
  double fitRoll(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays) const;
  // Whether the static scene's model (a fitted translation) fits the points better with that turn
  // taken out than without it (truncated squared residuals, capped at threshold_px). A camera
  // moving sideways past a floor sees more motion below than above, a shear whose turn fitRoll
  // finds too (0.002-0.004 rad per frame on the simulator's rooms, with no gyro bias): the
  // translation explains the shear, and explains it worse with that turn removed. A bias turn is
  // the other way round. (Comparing with the rotation-only model instead refused the real bias of
  // the moving-box flights: their gyro's bias about x and y, half a pixel per frame, is left for
  // the translation to absorb.)
  bool turnExplainsMore(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays,
                        double roll_rad);
  // The translation's fit and its truncated squared residuals (threshold_px squared at most per point).
  double translationCost(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays);
  // The translation direction the points agree with best (RANSAC, then least squares).
  Eigen::Vector3d fitTranslation(const std::vector<Eigen::Vector3d>& previous_rays,
                                 const std::vector<Eigen::Vector3d>& rays);
  // corner[i]: whether moving[i] is a corner (min_corner_points).
  std::vector<Detection> group(const std::vector<cv::Point2f>& moving, const std::vector<bool>& corner) const;
  int cellOf(const cv::Point2f& pixel) const;
  static bool isStill(const Track& t);
  // KLT of the points `which` from `from` in the previous frame (started at *to) into `pyramid`
  // over `levels`, checked by tracking back and by the window's mean difference (at most
  // max_error grey levels): *to and *tracked set at those indices.
  void trackPoints(const std::vector<cv::Mat>& pyramid, int levels, double max_error,
                   const std::vector<size_t>& which, const std::vector<cv::Point2f>& from,
                   std::vector<cv::Point2f>* to, std::vector<uint8_t>* tracked) const;
  // One track per grid cell (the rays of the kept tracks kept beside them).
  void keepOnePerCell(std::vector<Eigen::Vector3d>* previous_rays, std::vector<Eigen::Vector3d>* rays);
  void topUp(const cv::Mat& grey);

  data::CameraModel camera_;
  MotionCueOptions options_;
  double focal_px_;
  int grid_cols_, grid_rows_;  // cells of cell_px over the camera's image
  std::vector<cv::Mat> previous_pyramid_;  // of the previous frame, for KLT
  std::vector<Track> tracks_;
  std::vector<MotionCuePoint> points_;
  bool translating_ = false;
  double roll_rad_ = 0;
  uint64_t rng_state_ = 0x9e3779b97f4a7c15ULL;  // RANSAC's samples: reproducible runs
};

}  // namespace adugs::tracking

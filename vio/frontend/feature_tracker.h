#pragma once
// The visual front-end of doc/architecture.md ("The method"): KLT tracking frame to frame, removal
// of features on dynamic objects, and compensation with new ORB/FAST corners spread by ANMS.
//
// trackFrame(t, image, mask), per frame:
//   1. pyramidal KLT (ViSP vpKltOpencv) of the previous features into the image, from their old
//      positions or, after setPredictedRotation(), from positions pre-warped by that rotation;
//      points off the image border are lost;
//   2. forward-backward check: track back and drop points whose round trip misses by more than
//      fb_threshold_px (vpKltOpencv has no such check);
//   3. tracked points inside the dynamic mask (nonzero = dynamic) are dropped: r of the s tracked;
//   4. RANSAC fundamental matrix on the remaining undistorted points drops outliers
//      (s counts the points that survive 1, 2 and 4; r the dynamic ones among them);
//   4b. each surviving point is refined by aligning the patch where it was first seen (its
//      anchor, vio/frontend/anchor_patch.h) to the image, so KLT's frame-to-frame errors do not add up;
//   5. new ORB (FAST score) corners outside the mask and at least D_min from the kept features,
//      thinned by ANMS to exactly N_max - s + r (fewer only when the image has too few corners),
//      so every frame ends with N_max features.
// Features carry a stable id, their lifetime in frames, and their velocity in normalised
// coordinates per second (the time-offset estimator's input, as in VINS-Mono).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "data/camera_model.h"
#include "vio/frontend/anchor_patch.h"
#include "vio/frontend/feature_tracker_options.h"
#include "vio/frontend/frame_features.h"

namespace adugs::vio {

struct FrameStats {
  int64_t t_ns = 0;
  int previous = 0;           // features handed in from the previous frame
  int lost_klt = 0;           // KLT failed or the point left the image (border)
  int rejected_fb = 0;        // forward-backward round trip too far
  int rejected_ransac = 0;    // fundamental-matrix outliers
  int rejected_outliers = 0;  // rejected_fb + rejected_ransac
  int tracked = 0;            // s: tracked and geometrically consistent (dynamic ones included)
  int dropped_dynamic = 0;    // r: tracked points that fell inside the dynamic mask
  int requested = 0;          // N_max - s + r
  int new_points = 0;         // what detection delivered (== requested unless corners ran out)
  int total = 0;              // features after this frame: s - r + new_points
  double mean_lifetime = 0;   // mean track count of the output features
  int reanchored = 0;         // tracked points whose anchor fit failed (KLT kept, new anchor)
  // Milliseconds per stage.
  double klt_ms = 0, fb_ms = 0, anchor_ms = 0, ransac_ms = 0, detect_ms = 0, anms_ms = 0, total_ms = 0;
};

class FeatureTracker {
 public:
  // Throws std::invalid_argument for nonsensical options.
  FeatureTracker(const FeatureTrackerOptions& options, const data::CameraModel& camera);
  ~FeatureTracker();
  FeatureTracker(const FeatureTracker&) = delete;
  FeatureTracker& operator=(const FeatureTracker&) = delete;

  // image: CV_8UC1 of the camera's size. mask: empty (no dynamic objects) or CV_8UC1 of the same
  // size, nonzero = dynamic. t_ns must increase from call to call. Throws std::invalid_argument
  // otherwise.
  FrameFeatures trackFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& mask = cv::Mat());

  // IMU hook: the rotation of the camera between the previous frame and the next one to be
  // tracked, R_Cprev_Ccur (maps vectors in the new camera frame into the previous one; gyro
  // integration gives R_Bprev_Bcur, and R_Cprev_Ccur = R_B_C^T R_Bprev_Bcur R_B_C). KLT then
  // starts each point where that rotation moves it. Used by the next trackFrame only.
  void setPredictedRotation(const Eigen::Matrix3d& R_Cprev_Ccur);

  const FrameStats& lastStats() const { return stats_; }
  // Pixels (in the last image) of the points dropped as dynamic / rejected as outliers.
  const std::vector<cv::Point2f>& lastDroppedDynamic() const { return dropped_dynamic_; }
  const std::vector<cv::Point2f>& lastRejectedOutliers() const { return rejected_; }
  const FrameFeatures& lastFeatures() const { return current_; }

  const FeatureTrackerOptions& options() const { return options_; }
  const data::CameraModel& camera() const { return camera_; }

 private:
  struct Impl;  // the ViSP trackers and the ORB detector, kept out of this header

  void track(const cv::Mat& image, const cv::Mat& mask, FrameFeatures* out);
  void detect(const cv::Mat& image, const cv::Mat& mask, FrameFeatures* out);
  // The feature's anchor (vio/frontend/anchor_patch.h) and the affine warp of its last fit.
  struct Anchor {
    std::shared_ptr<const AnchorPatch> patch;
    Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  };
  Anchor makeAnchor(const cv::Mat& image, const cv::Point2f& p) const;
  // Refines a KLT position against the feature's anchor; re-anchors when the fit is not trusted.
  void refineWithAnchor(const cv::Mat& image, cv::Point2f* position, Anchor* anchor);

  FeatureTrackerOptions options_;
  data::CameraModel camera_;
  std::unique_ptr<Impl> impl_;
  cv::Mat prev_image_;
  FrameFeatures current_;  // the last frame's output = the next frame's input
  std::vector<Anchor> anchors_, next_anchors_;  // index-aligned with current_ / the output
  bool has_prev_ = false;
  int64_t next_id_ = 0;
  bool has_prediction_ = false;
  Eigen::Matrix3d R_Cprev_Ccur_ = Eigen::Matrix3d::Identity();
  FrameStats stats_;
  std::vector<cv::Point2f> dropped_dynamic_, rejected_;
  cv::Mat detection_mask_;  // reused buffer
};

}  // namespace adugs::vio

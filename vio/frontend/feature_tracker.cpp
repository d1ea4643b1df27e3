#include "vio/frontend/feature_tracker.h"

#include <visp3/klt/vpKltOpencv.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "data/elapsed_time.h"
#include "vio/frontend/anms.h"
#include "vio/frontend/feature_detector.h"
#include "vio/frontend/feature_ransac.h"

namespace adugs::vio {
namespace {

using Clock = std::chrono::steady_clock;

bool isDynamic(const cv::Mat& mask, const cv::Point2f& p) {
  if (mask.empty()) return false;
  const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, mask.cols - 1);
  const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, mask.rows - 1);
  return mask.at<uchar>(y, x) != 0;
}

void validateOptions(const FeatureTrackerOptions& o) {
  const bool ok = o.max_features >= 1 && o.min_distance_px >= 0 && o.klt_window_px >= 3 &&
                  o.klt_pyramid_levels >= 0 && o.fb_pyramid_levels >= 0 && o.klt_min_eigen >= 0 &&
                  o.border_px >= 0 && o.fb_threshold_px >= 0 && o.ransac_threshold_px > 0 &&
                  o.ransac_confidence > 0 && o.ransac_confidence < 1 && o.fast_threshold >= 1 &&
                  o.max_candidates >= 1 && o.detection_border_px >= 0 &&
                  o.anchor_patch_half_px >= 2 && o.anchor_max_correction_px >= 0 &&
                  o.anchor_max_scale >= 1;
  if (!ok) throw std::invalid_argument("FeatureTracker: invalid FeatureTrackerOptions");
}

// The estimator works on (x, y, 1) rays: a pixel whose ray is 89 degrees or more off-axis, or
// that has no ray (outside a wide-angle lens' image circle), cannot be a feature.
const double kMinRayZ = std::cos(89.0 * M_PI / 180.0);

bool hasForwardRay(const data::CameraModel& camera, const cv::Point2f& p) {
  Eigen::Vector3d ray;
  return camera.unproject(Eigen::Vector2d(p.x, p.y), &ray) && ray.z() > kMinRayZ;
}

}  // namespace

// vpKltOpencv keeps the previous image and the point list itself, and track(I) runs OpenCV's
// pyramidal LK from its stored image into I. The forward tracker therefore persists across
// frames (after track(I) it holds I, the next frame's "previous"); each frame we hand it the
// current point list through setInitialGuess(points, guesses, ids), which also turns on
// OPTFLOW_USE_INITIAL_FLOW for the rotation-predicted guesses. Its ids are our indices into the
// previous frame's arrays, so the survivors map back without a lookup. Lost points are erased by
// ViSP (it exposes no status vector), which is all we need.
// The backward pass of the forward-backward check is a second vpKltOpencv primed with the
// current image (initTracking) and tracked into the previous one, starting at the original
// positions - vpKltOpencv cannot track given points between two arbitrary images in one call.
struct FeatureTracker::Impl {
  vpKltOpencv forward, backward;
};

FeatureTracker::FeatureTracker(const FeatureTrackerOptions& options,
                               const data::CameraModel& camera)
    : options_(options), camera_(camera), impl_(std::make_unique<Impl>()) {
  validateOptions(options_);
  if (camera_.width() <= 0 || camera_.height() <= 0)
    throw std::invalid_argument("FeatureTracker: camera model has no image size");
  for (vpKltOpencv* k : {&impl_->forward, &impl_->backward}) {
    k->setWindowSize(options_.klt_window_px);
    k->setMinEigThreshold(options_.klt_min_eigen);
  }
  impl_->forward.setPyramidLevels(options_.klt_pyramid_levels);
  // The backward pass starts at the true previous position, so a correct track needs no search:
  // fewer levels only make it cheaper (a wrong track still lands off its start).
  impl_->backward.setPyramidLevels(options_.fb_pyramid_levels);
}

FeatureTracker::~FeatureTracker() = default;

void FeatureTracker::setPredictedRotation(const Eigen::Matrix3d& R_Cprev_Ccur) {
  R_Cprev_Ccur_ = R_Cprev_Ccur;
  has_prediction_ = true;
}

FrameFeatures FeatureTracker::trackFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& mask) {
  if (image.type() != CV_8UC1 || image.cols != camera_.width() || image.rows != camera_.height())
    throw std::invalid_argument(
        "FeatureTracker::trackFrame: image must be CV_8UC1 of the camera's "
        "size " +
        std::to_string(camera_.width()) + "x" + std::to_string(camera_.height()));
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != image.size()))
    throw std::invalid_argument(
        "FeatureTracker::trackFrame: mask must be empty or CV_8UC1 of the "
        "image's size");
  if (has_prev_ && t_ns <= current_.t_ns)
    throw std::invalid_argument("FeatureTracker::trackFrame: timestamps must increase");

  const auto t0 = Clock::now();
  stats_ = FrameStats{};
  stats_.t_ns = t_ns;
  dropped_dynamic_.clear();
  rejected_.clear();

  FrameFeatures out;
  out.t_ns = t_ns;
  next_anchors_.clear();
  track(image, mask, &out);
  detect(image, mask, &out);
  anchors_.swap(next_anchors_);

  stats_.total = static_cast<int>(out.size());
  stats_.mean_lifetime =
      out.size() ? std::accumulate(out.track_counts.begin(), out.track_counts.end(), 0.0) /
                       static_cast<double>(out.size())
                 : 0.0;
  image.copyTo(prev_image_);
  current_ = out;
  has_prev_ = true;
  has_prediction_ = false;
  stats_.total_ms = data::msSince(t0);
  return out;
}

void FeatureTracker::track(const cv::Mat& image, const cv::Mat& mask, FrameFeatures* out) {
  const FrameFeatures& prev = current_;
  const size_t n = has_prev_ ? prev.size() : 0;
  stats_.previous = static_cast<int>(n);
  if (n == 0) {
    // Nothing to track; the tracker still has to hold this image as the next "previous".
    impl_->forward.initTracking(image, std::vector<cv::Point2f>{}, std::vector<long>{});
    return;
  }

  // 1. Forward KLT, from the old positions or from where the predicted rotation moves them.
  auto t = Clock::now();
  std::vector<cv::Point2f> guesses = prev.pixels;
  if (has_prediction_) {
    const Eigen::Matrix3d R_Ccur_Cprev = R_Cprev_Ccur_.transpose();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d f = R_Ccur_Cprev * prev.normalized[i].homogeneous();
      if (f.z() < 1e-3) continue;  // rotated behind the camera: keep the old position
      const Eigen::Vector2d uv = camera_.normalizedToPixel(f.head<2>() / f.z());
      guesses[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
  }
  std::vector<long> index(n);
  std::iota(index.begin(), index.end(), 0L);
  impl_->forward.setInitialGuess(prev.pixels, guesses, index);
  impl_->forward.track(image);
  const std::vector<cv::Point2f> fwd = impl_->forward.getFeatures();
  const std::vector<long> fwd_index = impl_->forward.getFeaturesId();
  std::vector<int> src;  // index into prev of each candidate
  std::vector<cv::Point2f> cur;
  for (size_t k = 0; k < fwd.size(); ++k) {
    if (!camera_.inImage(fwd[k].x, fwd[k].y, options_.border_px) || !hasForwardRay(camera_, fwd[k]))
      continue;
    src.push_back(static_cast<int>(fwd_index[k]));
    cur.push_back(fwd[k]);
  }
  stats_.lost_klt = static_cast<int>(n - cur.size());
  stats_.klt_ms = data::msSince(t);

  // 2. Forward-backward check.
  t = Clock::now();
  if (options_.fb_check && !cur.empty()) {
    std::vector<cv::Point2f> start(cur.size());
    std::vector<long> local(cur.size());
    for (size_t k = 0; k < cur.size(); ++k) start[k] = prev.pixels[src[k]], local[k] = long(k);
    impl_->backward.initTracking(image, cur, local);
    impl_->backward.setInitialGuess(cur, start, local);
    impl_->backward.track(prev_image_);
    const std::vector<cv::Point2f> back = impl_->backward.getFeatures();
    const std::vector<long> back_index = impl_->backward.getFeaturesId();
    std::vector<bool> ok(cur.size(), false);
    const float thr2 = static_cast<float>(options_.fb_threshold_px * options_.fb_threshold_px);
    for (size_t k = 0; k < back.size(); ++k) {
      const cv::Point2f d = back[k] - start[back_index[k]];
      ok[back_index[k]] = d.dot(d) <= thr2;
    }
    size_t w = 0;
    for (size_t k = 0; k < cur.size(); ++k) {
      if (!ok[k]) {
        rejected_.push_back(cur[k]);
        continue;
      }
      src[w] = src[k], cur[w] = cur[k], ++w;
    }
    stats_.rejected_fb = static_cast<int>(cur.size() - w);
    src.resize(w), cur.resize(w);
  }
  stats_.fb_ms = data::msSince(t);

  // 3. Dynamic points out (counted: r), 4. RANSAC on the static rest.
  t = Clock::now();
  std::vector<Eigen::Vector2d> cur_norm;
  camera_.pixelsToNormalized(cur, &cur_norm);
  std::vector<size_t> stat;  // candidates outside the mask
  for (size_t k = 0; k < cur.size(); ++k) {
    if (isDynamic(mask, cur[k])) {
      dropped_dynamic_.push_back(cur[k]);
    } else {
      stat.push_back(k);
    }
  }
  stats_.dropped_dynamic = static_cast<int>(dropped_dynamic_.size());
  std::vector<bool> inlier(stat.size(), true);
  if (options_.ransac) {
    std::vector<Eigen::Vector2d> a(stat.size()), b(stat.size());
    for (size_t j = 0; j < stat.size(); ++j)
      a[j] = prev.normalized[src[stat[j]]], b[j] = cur_norm[stat[j]];
    FundamentalRansacOptions ro;
    ro.focal_px = camera_.centreFocalPx();
    ro.threshold_px = options_.ransac_threshold_px;
    ro.confidence = options_.ransac_confidence;
    inlier = fundamentalInliers(a, b, ro);
  }
  stats_.ransac_ms = data::msSince(t);
  t = Clock::now();
  const double dt = 1e-9 * static_cast<double>(out->t_ns - prev.t_ns);
  for (size_t j = 0; j < stat.size(); ++j) {
    const size_t k = stat[j];
    if (!inlier[j]) {
      rejected_.push_back(cur[k]);
      ++stats_.rejected_ransac;
      continue;
    }
    const int i = src[k];
    if (options_.anchor_alignment) {
      Anchor anchor = std::move(anchors_[i]);  // anchors_ is replaced after this frame
      const cv::Point2f klt = cur[k];
      refineWithAnchor(image, &cur[k], &anchor);
      if (cur[k] != klt) cur_norm[k] = camera_.pixelToNormalized({cur[k].x, cur[k].y});
      next_anchors_.push_back(std::move(anchor));
    } else {
      next_anchors_.emplace_back();
    }
    out->ids.push_back(prev.ids[i]);
    out->pixels.push_back(cur[k]);
    out->prev_pixels.push_back(prev.pixels[i]);
    out->normalized.push_back(cur_norm[k]);
    out->track_counts.push_back(prev.track_counts[i] + 1);
    out->velocities.push_back((cur_norm[k] - prev.normalized[i]) / dt);
  }
  stats_.rejected_outliers = stats_.rejected_fb + stats_.rejected_ransac;
  stats_.tracked = static_cast<int>(out->size()) + stats_.dropped_dynamic;
  stats_.anchor_ms = data::msSince(t);
}

FeatureTracker::Anchor FeatureTracker::makeAnchor(const cv::Mat& image, const cv::Point2f& p) const {
  Anchor a;
  if (options_.anchor_alignment)
    a.patch = std::make_shared<const AnchorPatch>(image, Eigen::Vector2d(p.x, p.y),
                                                  options_.anchor_patch_half_px);
  return a;
}

void FeatureTracker::refineWithAnchor(const cv::Mat& image, cv::Point2f* position,
                                      Anchor* anchor) {
  const Eigen::Vector2d klt(position->x, position->y);
  if (anchor->patch && anchor->patch->valid()) {
    // Started at the KLT position with the last warp, a fit that will converge does so in 2-3
    // steps; a cap of 5 keeps the ones that will not from costing 15 (sim street: ~7 % re-anchor).
    const AnchorPatch::Result r = anchor->patch->align(image, anchor->A, klt, 5);
    const double scale = std::sqrt(std::abs(r.A.determinant()));
    if (r.converged && (r.position - klt).norm() <= options_.anchor_max_correction_px &&
        r.zncc >= options_.anchor_min_zncc && scale <= options_.anchor_max_scale &&
        scale >= 1.0 / options_.anchor_max_scale) {
      *position = cv::Point2f(static_cast<float>(r.position.x()), static_cast<float>(r.position.y()));
      anchor->A = r.A;
      return;
    }
  }
  // No trusted fit: the KLT position stands and becomes the new anchor.
  ++stats_.reanchored;
  *anchor = makeAnchor(image, *position);
}

void FeatureTracker::detect(const cv::Mat& image, const cv::Mat& mask, FrameFeatures* out) {
  // Compensation: s tracked, r of them dropped, so s - r remain and N_max - s + r restore N_max.
  stats_.requested = options_.max_features - stats_.tracked + stats_.dropped_dynamic;
  if (stats_.requested <= 0) return;

  auto t = Clock::now();
  // Detection mask: not dynamic and not within D_min of a kept feature. The circles only save
  // candidates; ANMS below enforces D_min exactly.
  if (mask.empty()) {
    detection_mask_.create(image.size(), CV_8UC1);
    detection_mask_.setTo(255);
  } else {
    cv::compare(mask, 0, detection_mask_, cv::CMP_EQ);
  }
  const int radius = static_cast<int>(options_.min_distance_px);
  if (radius > 0) {
    for (const cv::Point2f& p : out->pixels)
      cv::circle(detection_mask_, cv::Point(cvRound(p.x), cvRound(p.y)), radius, 0, cv::FILLED);
  }
  std::vector<cv::KeyPoint> candidates;
  detectOrbCorners(image, detection_mask_, options_, &candidates);
  stats_.detect_ms = data::msSince(t);

  t = Clock::now();
  const std::vector<int> chosen =
      selectAnms(candidates, stats_.requested, options_.min_distance_px, out->pixels);
  int added = 0;
  for (int c : chosen) {
    const cv::Point2f p = candidates[c].pt;
    if (!hasForwardRay(camera_, p)) continue;
    ++added;
    out->ids.push_back(next_id_++);
    out->pixels.push_back(p);
    out->prev_pixels.push_back(p);
    out->normalized.push_back(camera_.pixelToNormalized({p.x, p.y}));
    out->track_counts.push_back(1);
    out->velocities.push_back(Eigen::Vector2d::Zero());
    next_anchors_.push_back(makeAnchor(image, p));
  }
  stats_.new_points = added;
  stats_.anms_ms = data::msSince(t);
}

}  // namespace adugs::vio

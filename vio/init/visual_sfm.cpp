#include "vio/init/visual_sfm.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <sstream>
#include <unordered_map>

#include "vio/init/sfm_bundle_adjustment.h"

namespace adugs::vio {
namespace {

// Features seen in both frames, index-aligned.
struct Correspondences {
  std::vector<int64_t> ids;
  std::vector<Eigen::Vector2d> first, second;
};

Correspondences commonFeatures(const SfmFrameObservations& a, const SfmFrameObservations& b) {
  std::unordered_map<int64_t, size_t> index_in_b;
  for (size_t i = 0; i < b.ids.size(); ++i) index_in_b[b.ids[i]] = i;
  Correspondences c;
  for (size_t i = 0; i < a.ids.size(); ++i) {
    const auto it = index_in_b.find(a.ids[i]);
    if (it == index_in_b.end()) continue;
    c.ids.push_back(a.ids[i]);
    c.first.push_back(a.normalized[i]);
    c.second.push_back(b.normalized[it->second]);
  }
  return c;
}

std::vector<cv::Point2d> toCv(const std::vector<Eigen::Vector2d>& points) {
  std::vector<cv::Point2d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.emplace_back(p.x(), p.y());
  return out;
}

// Pose of the second camera in the first (unit baseline) from the essential matrix.
bool poseFromEssential(const Correspondences& c, double threshold, SfmPose* pose_first_second,
                       int* inliers) {
  try {
    const auto p1 = toCv(c.first), p2 = toCv(c.second);
    cv::Mat mask;
    const cv::Mat E =
        cv::findEssentialMat(p1, p2, 1.0, cv::Point2d(0, 0), cv::RANSAC, 0.999, threshold, mask);
    if (E.rows < 3 || E.cols != 3) return false;
    cv::Mat R, t;
    // recoverPose: x2 = R x1 + t (first -> second); keeps the inliers in front of both cameras.
    *inliers = cv::recoverPose(E.rowRange(0, 3), p1, p2, R, t, 1.0, cv::Point2d(0, 0), mask);
    Eigen::Matrix3d R_21;
    Eigen::Vector3d t_21;
    cv::cv2eigen(R, R_21);
    cv::cv2eigen(t, t_21);
    if (!R_21.allFinite() || !t_21.allFinite() || t_21.norm() < 1e-9) return false;
    pose_first_second->R_R_C = R_21.transpose();
    pose_first_second->p_R_C = -R_21.transpose() * t_21.normalized();
    return true;
  } catch (const cv::Exception&) {
    return false;
  }
}

// PnP (EPnP RANSAC, then Levenberg-Marquardt on the inliers) of one frame from known points.
bool poseFromPnp(const std::vector<Eigen::Vector3d>& points_R,
                 const std::vector<Eigen::Vector2d>& normalized, const VisualSfmOptions& options,
                 SfmPose* pose, int* inlier_count) {
  *inlier_count = 0;
  if (static_cast<int>(points_R.size()) < std::max(options.min_pnp_inliers, 6)) return false;
  try {
    std::vector<cv::Point3d> object;
    for (const auto& p : points_R) object.emplace_back(p.x(), p.y(), p.z());
    const auto image = toCv(normalized);
    const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, 200,
                            options.max_reprojection_px / options.focal_px, 0.999, inliers,
                            cv::SOLVEPNP_EPNP))
      return false;
    *inlier_count = static_cast<int>(inliers.size());
    if (*inlier_count < options.min_pnp_inliers) return false;
    std::vector<cv::Point3d> object_in;
    std::vector<cv::Point2d> image_in;
    for (int i : inliers) {
      object_in.push_back(object[i]);
      image_in.push_back(image[i]);
    }
    cv::solvePnPRefineLM(object_in, image_in, K, cv::noArray(), rvec, tvec);
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d R_CR;
    Eigen::Vector3d t_CR;
    cv::cv2eigen(R, R_CR);
    cv::cv2eigen(tvec, t_CR);
    if (!R_CR.allFinite() || !t_CR.allFinite()) return false;
    pose->R_R_C = R_CR.transpose();
    pose->p_R_C = -R_CR.transpose() * t_CR;
    return true;
  } catch (const cv::Exception&) {
    return false;
  }
}

// All observations of every feature id: (frame, normalised point).
std::map<int64_t, std::vector<SfmObservation>> collectTracks(
    const std::vector<SfmFrameObservations>& frames) {
  std::map<int64_t, std::vector<SfmObservation>> tracks;
  for (size_t f = 0; f < frames.size(); ++f)
    for (size_t i = 0; i < frames[f].ids.size(); ++i)
      tracks[frames[f].ids[i]].push_back({static_cast<int>(f), frames[f].normalized[i]});
  return tracks;
}

// Triangulates every not yet known track seen by >= 2 posed frames with enough ray angle.
void triangulateNewPoints(const std::map<int64_t, std::vector<SfmObservation>>& tracks,
                          const std::vector<SfmPose>& poses, const std::vector<bool>& posed,
                          std::map<int64_t, Eigen::Vector3d>* points) {
  constexpr double kMinRayAngleRad = 0.5 * M_PI / 180.0;  // below this depth is noise
  for (const auto& [id, observations] : tracks) {
    if (points->count(id)) continue;
    std::vector<SfmView> views;
    for (const auto& obs : observations)
      if (posed[obs.frame]) views.push_back({&poses[obs.frame], obs.normalized});
    if (views.size() < 2) continue;
    const Eigen::Vector3d ray_first =
        views.front().pose->R_R_C * views.front().normalized.homogeneous();
    const Eigen::Vector3d ray_last =
        views.back().pose->R_R_C * views.back().normalized.homogeneous();
    const double angle = std::atan2(ray_first.cross(ray_last).norm(), ray_first.dot(ray_last));
    if (angle < kMinRayAngleRad) continue;
    Eigen::Vector3d point;
    if (triangulateLinear(views, &point)) (*points)[id] = point;
  }
}

std::string describe(const std::string& what, double value, double needed) {
  std::ostringstream out;
  out.precision(3);
  out << what << " " << value << " (need " << needed << ")";
  return out.str();
}

}  // namespace

VisualSfmResult runVisualSfm(const std::vector<SfmFrameObservations>& frames,
                             const VisualSfmOptions& options) {
  VisualSfmResult result;
  auto fail = [&result](const std::string& why) {
    result.success = false;
    result.failure_reason = "SfM: " + why;
    return result;
  };
  const int n = static_cast<int>(frames.size());
  if (n < 2) return fail("fewer than 2 frames");
  for (int k = 0; k < n; ++k) {
    if (frames[k].ids.size() != frames[k].normalized.size())
      return fail("frame " + std::to_string(k) + ": ids and points differ in number");
    for (const auto& p : frames[k].normalized)
      if (!p.allFinite())
        return fail("frame " + std::to_string(k) + ": non-finite feature coordinate");
  }

  // 1. The pair: most translation parallax among frames sharing enough features with frame 0.
  int best_common = 0;
  double best_raw = 0, best_translation = 0;
  int pair = -1;
  Correspondences pair_matches;
  for (int k = 1; k < n; ++k) {
    Correspondences c = commonFeatures(frames[0], frames[k]);
    const int common = static_cast<int>(c.ids.size());
    best_common = std::max(best_common, common);
    if (common < options.min_common_features) continue;
    const double raw = meanDisplacement(c.first, c.second) * options.focal_px;
    best_raw = std::max(best_raw, raw);
    if (raw < options.min_parallax_px) continue;
    const double translation = rotationCompensatedParallax(c.first, c.second) * options.focal_px;
    if (translation > best_translation) {
      best_translation = translation;
      if (translation >= options.min_translation_parallax_px) {
        pair = k;
        result.pair_parallax_px = raw;
        result.pair_translation_parallax_px = translation;
        pair_matches = std::move(c);
      }
    }
  }
  if (best_common < options.min_common_features)
    return fail(describe("too few common features with the first frame: best", best_common,
                         options.min_common_features));
  if (best_raw < options.min_parallax_px)
    return fail(describe("not enough parallax: best mean feature motion [px]", best_raw,
                         options.min_parallax_px));
  if (pair < 0)
    return fail(
        describe("not enough translation parallax (rotation-only motion?): best parallax "
                 "after removing the rotation [px]",
                 best_translation, options.min_translation_parallax_px));
  result.pair_frame = pair;

  // 2. Relative pose of the pair.
  std::vector<SfmPose> poses(n);
  std::vector<bool> posed(n, false);
  int essential_inliers = 0;
  if (!poseFromEssential(pair_matches, options.max_reprojection_px / options.focal_px, &poses[pair],
                         &essential_inliers))
    return fail("essential matrix / recoverPose failed");
  if (essential_inliers < options.min_common_features / 2)
    return fail(describe("essential matrix has too few inliers in front of the cameras:",
                         essential_inliers, options.min_common_features / 2));
  posed[0] = posed[pair] = true;

  // 3. Triangulate, then PnP outward from the pair, triangulating after each new frame.
  const auto tracks = collectTracks(frames);
  std::map<int64_t, Eigen::Vector3d> points;
  triangulateNewPoints(tracks, poses, posed, &points);
  std::vector<int> order;
  for (int j = 1; j < pair; ++j) order.push_back(j);
  for (int j = pair + 1; j < n; ++j) order.push_back(j);
  for (int j : order) {
    std::vector<Eigen::Vector3d> known;
    std::vector<Eigen::Vector2d> observed;
    for (size_t i = 0; i < frames[j].ids.size(); ++i) {
      const auto it = points.find(frames[j].ids[i]);
      if (it == points.end()) continue;
      known.push_back(it->second);
      observed.push_back(frames[j].normalized[i]);
    }
    int inliers = 0;
    if (!poseFromPnp(known, observed, options, &poses[j], &inliers)) {
      std::ostringstream why;
      why << "PnP failed for frame " << j << " (" << known.size() << " known points, " << inliers
          << " inliers, need " << options.min_pnp_inliers << ")";
      return fail(why.str());
    }
    posed[j] = true;
    triangulateNewPoints(tracks, poses, posed, &points);
  }

  // 4. Bundle adjustment, drop outliers, adjust again.
  SfmBundleProblem ba;
  ba.poses = poses;
  ba.fixed_frame = 0;
  ba.fixed_position_frame = pair;
  SfmBundleOptions ba_options;
  ba_options.focal_px = options.focal_px;
  for (int round = 0; round < 2; ++round) {
    ba.points = points;
    ba.observations.clear();
    for (const auto& [id, point] : points) ba.observations[id] = tracks.at(id);
    if (!bundleAdjust(ba, ba_options)) return fail("bundle adjustment failed");
    points.clear();
    double error_sum = 0;
    int error_count = 0;
    for (const auto& [id, point] : ba.points) {
      double worst = 0, sum = 0;
      for (const auto& obs : ba.observations.at(id)) {
        const double e =
            reprojectionError(ba.poses[obs.frame], point, obs.normalized) * options.focal_px;
        worst = std::max(worst, e);
        sum += e;
      }
      if (worst <= options.max_reprojection_px) {
        points[id] = point;
        error_sum += sum;
        error_count += static_cast<int>(ba.observations.at(id).size());
      }
    }
    result.mean_reprojection_px = error_count > 0 ? error_sum / error_count : 0.0;
    if (static_cast<int>(points.size()) == static_cast<int>(ba.points.size())) break;
  }
  if (static_cast<int>(points.size()) < options.min_landmarks)
    return fail(describe("too few landmarks survive the bundle adjustment:",
                         static_cast<double>(points.size()), options.min_landmarks));
  result.poses = ba.poses;
  result.points = std::move(points);
  result.success = true;
  return result;
}

}  // namespace adugs::vio

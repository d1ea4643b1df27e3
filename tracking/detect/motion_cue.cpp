#include "tracking/detect/motion_cue.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <Eigen/Eigenvalues>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

namespace adugs::tracking {
namespace {

// Angle between two unit rays.
double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Angle of b to the epipolar plane of a for the translation direction t (unit vectors); the
// plain angle between a and b where that plane is undefined (a along t: the epipole itself).
double epipolarAngle(const Eigen::Vector3d& t, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d normal = t.cross(a);
  const double n = normal.norm();
  if (n < 1e-9) return angleBetween(a, b);
  return std::asin(std::min(1.0, std::abs(normal.dot(b)) / n));
}

// A still point tracked on few levels is kept when its window's mean absolute difference is at
// most this (grey levels), else it is tracked again on all. On a textured scene a point that
// jumped beyond those levels' reach converges on the wrong texture and still passes the back
// check (that starts at the original point): its difference is 14-40. On a moving-box flight 89 %
// of the still points' tracks are below 2, and 0.5 % above 8 pass the back check.
constexpr double kStillMaxErrorGrey = 8;

// The smallest turn about the optical axis MotionCue::fitRoll reports, as the motion of the point
// farthest from the centre (pixels on the optical axis): a fifth of the default threshold_px.
constexpr double kMinRollPx = 0.3;

// Disjoint sets for grouping the moving points.
int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

MotionCue::MotionCue(const data::CameraModel& camera, const MotionCueOptions& options)
    : camera_(camera),
      options_(options),
      focal_px_(camera.centreFocalPx()),
      grid_cols_((camera.width() + options.cell_px - 1) / std::max(1, options.cell_px)),
      grid_rows_((camera.height() + options.cell_px - 1) / std::max(1, options.cell_px)) {
  if (options_.cell_px < 4 || options_.klt_window_px < 5 || options_.klt_pyramid_levels < 0 || options_.still_pyramid_levels < 0 || options_.min_points < 1 || options_.min_corner_points < 0 || options_.corner_ratio < 0 || options_.corner_ratio > 1 || options_.threshold_px <= 0 ||
      options_.strong_threshold_px < options_.threshold_px || options_.group_radius_px <= 0 ||
      options_.ransac_iterations < 1 || options_.corner_quality <= 0)
    throw std::invalid_argument("MotionCue: cell_px >= 4, klt_window_px >= 5, klt_pyramid_levels >= 0, still_pyramid_levels >= 0, min_points >= 1, min_corner_points >= 0, corner_ratio in [0, 1] and positive thresholds, radius, quality and iterations");
}

std::vector<Detection> MotionCue::detect(const cv::Mat& image, const Eigen::Matrix3d& R_Ccur_Cprev,
                                         const std::optional<Eigen::Vector3d>& v_C, double dt_s) {
  cv::Mat grey;
  if (image.type() == CV_8UC3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.type() == CV_8UC1) grey = image;
  else throw std::invalid_argument("MotionCue: the image must be CV_8UC1 or CV_8UC3");
  if (grey.cols != camera_.width() || grey.rows != camera_.height())
    throw std::invalid_argument("MotionCue: a " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                                " image for a " + std::to_string(camera_.width()) + "x" +
                                std::to_string(camera_.height()) + " camera");
  points_.clear();
  translating_ = false;
  // Pyramids are built once per frame and kept for the next one.
  const int levels = options_.klt_pyramid_levels;
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(grey, pyramid, cv::Size(options_.klt_window_px, options_.klt_window_px), levels);
  if (previous_pyramid_.empty() || previous_pyramid_[0].size() != grey.size()) {
    tracks_.clear();
    previous_pyramid_ = std::move(pyramid);
    topUp(grey);
    return {};
  }

  // 1. The previous points tracked into this frame, started where the rotation puts them plus
  //    the drift they had after it last frame (a static point's parallax changes slowly; an
  //    object's motion too, over a frame), checked by tracking back. A still point, so started,
  //    needs few pyramid levels; the others and the still ones lost that way take them all.
  const size_t n = tracks_.size();
  std::vector<cv::Point2f> from(n), to(n);
  std::vector<cv::Point2f> rotated(n);  // where the rotation alone puts each point
  std::vector<Eigen::Vector3d> from_rays(n);
  std::vector<size_t> near_pass, full_pass;
  for (size_t i = 0; i < n; ++i) {
    const Track& t = tracks_[i];
    Eigen::Vector2d predicted;
    if (!camera_.unproject(Eigen::Vector2d(t.pixel.x, t.pixel.y), &from_rays[i])) continue;
    if (!camera_.project(R_Ccur_Cprev * from_rays[i], &predicted)) predicted = Eigen::Vector2d(t.pixel.x, t.pixel.y);
    from[i] = t.pixel;
    rotated[i] = cv::Point2f(static_cast<float>(predicted.x()), static_cast<float>(predicted.y()));
    to[i] = rotated[i] + t.drift;
    (isStill(t) ? near_pass : full_pass).push_back(i);
  }
  std::vector<uint8_t> tracked(n, 0);
  trackPoints(pyramid, std::min(levels, options_.still_pyramid_levels), kStillMaxErrorGrey, near_pass, from, &to, &tracked);
  for (size_t i : near_pass)
    if (!tracked[i]) to[i] = rotated[i], full_pass.push_back(i);
  trackPoints(pyramid, levels, std::numeric_limits<double>::infinity(), full_pass, from, &to, &tracked);

  std::vector<Eigen::Vector3d> previous_rays, rays;
  std::vector<Track> kept;
  for (size_t i = 0; i < n; ++i) {
    if (!tracked[i] || !camera_.inImage(to[i].x, to[i].y, 1.0)) continue;
    Eigen::Vector3d b;
    if (!camera_.unproject(Eigen::Vector2d(to[i].x, to[i].y), &b)) continue;
    // 2. The camera's rotation removed: where the previous ray points in this camera.
    previous_rays.push_back((R_Ccur_Cprev * from_rays[i]).normalized());
    rays.push_back(b.normalized());
    kept.push_back({to[i], to[i] - rotated[i], tracks_[i].history, static_cast<uint8_t>(std::min(255, tracks_[i].age + 1))});
  }
  tracks_ = std::move(kept);
  keepOnePerCell(&previous_rays, &rays);
  // 2b. Without the estimator's state its gyro bias is not known either: a turn about the optical
  //     axis that the points show is taken out when it explains them better than a translation.
  roll_rad_ = 0;
  if (!v_C) {
    const double w = fitRoll(previous_rays, rays);
    if (w != 0 && turnExplainsMore(previous_rays, rays, w)) {
      roll_rad_ = w;
      const Eigen::Matrix3d roll = Eigen::AngleAxisd(w, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      for (Eigen::Vector3d& a : previous_rays) a = roll * a;
    }
  }

  // 3-4. Residuals against the static scene's model; the votes of the last three frames.
  const std::vector<double> r = residuals(previous_rays, rays, v_C);
  // The known translation: b ~ range * a - d for a static point, so a x b = (d x a) / range.
  const Eigen::Vector3d d = v_C && translating_ && dt_s > 0 ? Eigen::Vector3d(*v_C * dt_s) : Eigen::Vector3d::Zero();
  std::vector<cv::Point2f> moving;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    t.history = static_cast<uint8_t>((t.history << 1) | (r[i] > options_.threshold_px ? 1 : 0));
    const bool moves = std::bitset<3>(t.history & 7u).count() >= 2 || r[i] > options_.strong_threshold_px;
    const bool still = isStill(t);
    MotionCuePoint p{t.pixel, moves, still, r[i]};
    const Eigen::Vector3d line = d.cross(previous_rays[i]);  // a x b of a static point, times its range
    if (const double n = line.norm(); n > 1e-12) {
      p.slide_at_1m_px = focal_px_ * n;
      p.slide_px = focal_px_ * previous_rays[i].cross(rays[i]).dot(line / n);
    }
    points_.push_back(p);
    if (moves) moving.push_back(t.pixel);
  }
  // The pyramid's second entry holds the frame's gradients (images and derivatives alternate).
  std::vector<bool> corner(moving.size(), true);
  if (options_.min_corner_points > 0)
    for (size_t i = 0; i < moving.size(); ++i)
      corner[i] = cornerRatio(pyramid[1], moving[i], options_.klt_window_px / 2) >= options_.corner_ratio;
  previous_pyramid_ = std::move(pyramid);
  topUp(grey);
  return group(moving, corner);
}

bool MotionCue::isStill(const Track& t) { return t.age >= 2 && (t.history & 3u) == 0; }

void MotionCue::trackPoints(const std::vector<cv::Mat>& pyramid, int levels, double max_error,
                            const std::vector<size_t>& which, const std::vector<cv::Point2f>& from,
                            std::vector<cv::Point2f>* to, std::vector<uint8_t>* tracked) const {
  if (which.empty()) return;
  std::vector<cv::Point2f> a, b, back;
  for (size_t i : which) a.push_back(from[i]), b.push_back((*to)[i]);
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  std::vector<uint8_t> ok, ok_back;
  std::vector<float> forward_error, error;
  cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid, a, b, ok, forward_error, window, levels,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.03),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  // Started at the original point, a consistent track needs no pyramid to come back: the check
  // runs on the full-resolution level alone, at a fraction of the forward cost.
  back = a;
  cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid_, b, back, ok_back, error, window, 0,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 5, 0.03),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t k = 0; k < which.size(); ++k) {
    (*to)[which[k]] = b[k];
    (*tracked)[which[k]] = ok[k] && ok_back[k] && cv::norm(back[k] - a[k]) <= 1.0 && forward_error[k] <= max_error;
  }
}

std::vector<double> MotionCue::residuals(const std::vector<Eigen::Vector3d>& previous_rays,
                                         const std::vector<Eigen::Vector3d>& rays,
                                         const std::optional<Eigen::Vector3d>& v_C) {
  const size_t n = rays.size();
  std::vector<double> rotation_only(n);
  for (size_t i = 0; i < n; ++i) rotation_only[i] = focal_px_ * angleBetween(previous_rays[i], rays[i]);
  if (n < 8 || (v_C && v_C->norm() < options_.min_speed)) return rotation_only;
  const Eigen::Vector3d t = v_C ? Eigen::Vector3d(v_C->normalized()) : fitTranslation(previous_rays, rays);

  // A static point slides along its epipolar line away from the direction of travel (b ~ depth
  // * a - t, so a x b points along t x a). A point sliding the other way moves: an object
  // overtaking the camera, whose motion lies along the epipolar line and would otherwise pass as
  // a far-away static point.
  std::vector<double> r(n);
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d& a = previous_rays[k];
    r[k] = focal_px_ * epipolarAngle(t, a, rays[k]);
    if (a.cross(rays[k]).dot(t.cross(a)) < 0) r[k] = std::max(r[k], rotation_only[k]);
  }
  // Which model, for a fitted direction: the translating one explains more, and it has two degrees of
  // freedom that can line up with moving objects if the static scene has no parallax; it is
  // taken when it explains clearly more points (a near road slides past a slow camera while the
  // far scene stays put: the median motion can be below a pixel and the translation still matter).
  const auto inliers = [&](const std::vector<double>& residual) {
    return std::count_if(residual.begin(), residual.end(), [&](double v) { return v < options_.threshold_px; });
  };
  // A known velocity is not fitted and cannot line up with a moving object: above min_speed the
  // camera translates, whether or not this frame's points show parallax (taking "rotation only"
  // while driving puts every near static point among the moving ones).
  const double gain = std::max(options_.translation_min_gain * static_cast<double>(n), 5.0);
  translating_ = v_C.has_value() || static_cast<double>(inliers(r) - inliers(rotation_only)) > gain;
  return translating_ ? r : rotation_only;
}

double MotionCue::fitRoll(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays) const {
  // A small turn by angle w about the optical axis z moves a ray a by w (z x a): each point's own
  // w is its motion along z x a over that vector's length. Their median (weighted by the length
  // squared, as far points say more) starts the estimate; least squares over the points it
  // explains within threshold_px refine it.
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  std::vector<std::pair<double, double>> votes;  // (w, weight)
  double total = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d t = z.cross(previous_rays[i]);
    const double w2 = t.squaredNorm();
    if (w2 < 1e-4) continue;  // near the image centre a turn moves nothing
    votes.push_back({(rays[i] - previous_rays[i]).dot(t) / w2, w2});
    total += w2;
  }
  if (votes.size() < 8) return 0;
  const double widest = std::sqrt(std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) {
                                    return a.second < b.second;
                                  })->second);  // |z x a| of the point farthest from the centre
  std::sort(votes.begin(), votes.end());
  double w = 0, below = 0;
  for (const auto& [v, weight] : votes)
    if ((below += weight) >= total / 2) {
      w = v;
      break;
    }
  const double threshold2 = std::pow(options_.threshold_px / focal_px_, 2);
  for (int round = 0; round < 2; ++round) {
    double num = 0, den = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const Eigen::Vector3d t = z.cross(previous_rays[i]);
      const Eigen::Vector3d e = rays[i] - previous_rays[i];
      if ((e - w * t).squaredNorm() > threshold2) continue;
      num += e.dot(t), den += t.squaredNorm();
    }
    if (den > 0) w = num / den;
  }
  // A turn that moves no point by kMinRollPx is within KLT's noise: none (and the simulator's
  // gyro, whose bias starts at zero, leaves the cue as it was).
  return std::abs(w) * widest * focal_px_ >= kMinRollPx ? w : 0.0;
}

bool MotionCue::turnExplainsMore(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays,
                                 double roll_rad) {
  // The static scene's model fitted twice, with the turn taken out and without: a bias turn leaves
  // the points a rigid scene once removed; the turn of a shear, removed, leaves them less so. Both
  // translation fits draw from the RANSAC generator: restored, so that a frame whose turn is not
  // taken goes on exactly as without this check.
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> turned(previous_rays.size());
  for (size_t i = 0; i < previous_rays.size(); ++i) turned[i] = roll * previous_rays[i];
  const uint64_t rng_state = rng_state_;
  const double with_turn = translationCost(turned, rays);
  rng_state_ = rng_state;
  const double without = translationCost(previous_rays, rays);
  rng_state_ = rng_state;
  return with_turn < without;
}

double MotionCue::translationCost(const std::vector<Eigen::Vector3d>& previous_rays, const std::vector<Eigen::Vector3d>& rays) {
  const Eigen::Vector3d t = fitTranslation(previous_rays, rays);
  const double cap = options_.threshold_px * options_.threshold_px;
  double cost = 0;
  for (size_t i = 0; i < rays.size(); ++i)
    cost += std::min(cap, std::pow(focal_px_ * epipolarAngle(t, previous_rays[i], rays[i]), 2));
  return cost;
}

Eigen::Vector3d MotionCue::fitTranslation(const std::vector<Eigen::Vector3d>& previous_rays,
                                          const std::vector<Eigen::Vector3d>& rays) {
  // The translation lies in every static point's epipolar plane (normal a x b), so two points'
  // normals give it.
  const size_t n = rays.size();
  std::vector<Eigen::Vector3d> normals(n);
  for (size_t i = 0; i < n; ++i) normals[i] = previous_rays[i].cross(rays[i]);
  const auto nextIndex = [&] {
    rng_state_ ^= rng_state_ << 13;  // xorshift64
    rng_state_ ^= rng_state_ >> 7;
    rng_state_ ^= rng_state_ << 17;
    return static_cast<size_t>(rng_state_ % n);
  };
  // Scored by the truncated squared residual (MSAC): with the small parallax of one frame many
  // directions keep every static point under the threshold, and the best of them fits tightest.
  const double threshold_rad = options_.threshold_px / focal_px_;
  const auto cost = [&](const Eigen::Vector3d& t) {
    double c = 0;
    for (size_t k = 0; k < n; ++k) c += std::min(std::pow(epipolarAngle(t, previous_rays[k], rays[k]), 2), threshold_rad * threshold_rad);
    return c;
  };
  Eigen::Vector3d best = Eigen::Vector3d::UnitZ();
  double best_cost = std::numeric_limits<double>::infinity();
  for (int it = 0; it < options_.ransac_iterations; ++it) {
    const size_t i = nextIndex(), j = nextIndex();
    if (i == j) continue;
    Eigen::Vector3d t = normals[i].cross(normals[j]);
    if (t.norm() < 1e-12) continue;
    t.normalize();
    if (const double c = cost(t); c < best_cost) best_cost = c, best = t;
  }
  // Refined on its inliers: the direction closest to perpendicular to all their plane normals
  // (least squares, the smallest eigenvector of the normals' scatter).
  for (int round = 0; round < 2; ++round) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < n; ++k)
      if (epipolarAngle(best, previous_rays[k], rays[k]) < threshold_rad) scatter += normals[k] * normals[k].transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    const Eigen::Vector3d refined = eigen.eigenvectors().col(0);
    if (cost(refined) <= cost(best)) best = refined;
  }
  // The sign: most points are static and slide away from the direction of travel.
  double vote = 0;
  for (size_t k = 0; k < n; ++k) vote += normals[k].dot(best.cross(previous_rays[k]));
  return vote < 0 ? Eigen::Vector3d(-best) : best;
}

double cornerRatio(const cv::Mat& gradients, const cv::Point2f& pixel, int radius) {
  if (gradients.type() != CV_16SC2) throw std::invalid_argument("cornerRatio: the gradients must be CV_16SC2");
  const int cx = static_cast<int>(std::lround(pixel.x)), cy = static_cast<int>(std::lround(pixel.y));
  double xx = 0, xy = 0, yy = 0;
  for (int y = std::max(0, cy - radius); y <= std::min(gradients.rows - 1, cy + radius); ++y)
    for (int x = std::max(0, cx - radius); x <= std::min(gradients.cols - 1, cx + radius); ++x) {
      const cv::Vec2s& g = gradients.at<cv::Vec2s>(y, x);
      xx += static_cast<double>(g[0]) * g[0];
      xy += static_cast<double>(g[0]) * g[1];
      yy += static_cast<double>(g[1]) * g[1];
    }
  // The eigenvalues of [xx xy; xy yy]: half the trace -+ the root of its square less the determinant.
  const double half_trace = (xx + yy) / 2;
  const double root = std::sqrt(std::max(0.0, half_trace * half_trace - (xx * yy - xy * xy)));
  return half_trace > 0 ? (half_trace - root) / (half_trace + root) : 0.0;
}

std::vector<Detection> MotionCue::group(const std::vector<cv::Point2f>& moving, const std::vector<bool>& corner) const {
  const int n = static_cast<int>(moving.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const double r2 = options_.group_radius_px * options_.group_radius_px;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const cv::Point2f d = moving[i] - moving[j];
      if (d.dot(d) <= r2) parent[findRoot(parent, i)] = findRoot(parent, j);
    }
  std::vector<std::vector<int>> members(n);
  for (int i = 0; i < n; ++i) members[findRoot(parent, i)].push_back(i);
  std::vector<Detection> boxes;
  for (const std::vector<int>& m : members) {
    if (static_cast<int>(m.size()) < options_.min_points) continue;
    if (std::count_if(m.begin(), m.end(), [&](int i) { return corner[static_cast<size_t>(i)]; }) < options_.min_corner_points) continue;
    double x0 = moving[m[0]].x, x1 = x0, y0 = moving[m[0]].y, y1 = y0;
    for (int i : m) {
      x0 = std::min<double>(x0, moving[i].x), x1 = std::max<double>(x1, moving[i].x);
      y0 = std::min<double>(y0, moving[i].y), y1 = std::max<double>(y1, moving[i].y);
    }
    // A point per cell: the object reaches up to half a cell past the outermost ones.
    const double mx = options_.box_margin * (x1 - x0) + options_.cell_px / 2.0;
    const double my = options_.box_margin * (y1 - y0) + options_.cell_px / 2.0;
    x0 = std::max(-0.5, x0 - mx), y0 = std::max(-0.5, y0 - my);
    x1 = std::min(camera_.width() - 0.5, x1 + mx), y1 = std::min(camera_.height() - 0.5, y1 + my);
    Detection d;
    d.box = Box::fromCorners(x0, y0, x1, y1);
    d.class_id = kMovingClass;
    d.score = 1.0;
    boxes.push_back(d);
  }
  return boxes;
}

int MotionCue::cellOf(const cv::Point2f& pixel) const {
  const int c = std::clamp(static_cast<int>(pixel.x) / options_.cell_px, 0, grid_cols_ - 1);
  const int r = std::clamp(static_cast<int>(pixel.y) / options_.cell_px, 0, grid_rows_ - 1);
  return r * grid_cols_ + c;
}

void MotionCue::keepOnePerCell(std::vector<Eigen::Vector3d>* previous_rays, std::vector<Eigen::Vector3d>* rays) {
  // Tracks drift together (an object's points crowd as it recedes, the top-up fills the cells the
  // scene left): the oldest point of a cell stays, it has the longest history.
  std::vector<uint8_t> taken(static_cast<size_t>(grid_cols_ * grid_rows_), 0);
  size_t kept = 0;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    uint8_t& cell = taken[static_cast<size_t>(cellOf(tracks_[i].pixel))];
    if (cell) continue;
    cell = 1;
    tracks_[kept] = tracks_[i];
    (*previous_rays)[kept] = (*previous_rays)[i];
    (*rays)[kept] = (*rays)[i];
    ++kept;
  }
  tracks_.resize(kept);
  previous_rays->resize(kept);
  rays->resize(kept);
}

void MotionCue::topUp(const cv::Mat& grey) {
  const int cell = options_.cell_px;
  std::vector<uint8_t> taken(static_cast<size_t>(grid_cols_ * grid_rows_), 0);
  for (const Track& t : tracks_) taken[static_cast<size_t>(cellOf(t.pixel))] = 1;
  // Corner strength at half resolution: a quarter of the cost, and a cell's best corner is
  // needed to a pixel only (KLT tracks the window around it). The pyramid has that level
  // (images and their derivatives alternate in it).
  cv::Mat half, strength;
  if (previous_pyramid_.size() > 2) half = previous_pyramid_[2];
  else cv::pyrDown(grey, half);
  cv::cornerMinEigenVal(half, strength, 3, 3);
  double strongest = 0;
  cv::minMaxLoc(strength, nullptr, &strongest);
  const double floor = std::max(1e-6, options_.corner_quality * strongest);
  for (int r = 0; r < grid_rows_; ++r)
    for (int c = 0; c < grid_cols_; ++c) {
      if (taken[static_cast<size_t>(r * grid_cols_ + c)]) continue;
      const cv::Rect area = cv::Rect(c * cell / 2, r * cell / 2, (cell + 1) / 2, (cell + 1) / 2) & cv::Rect(0, 0, half.cols, half.rows);
      if (area.empty()) continue;
      double best = 0;
      cv::Point at;
      cv::minMaxLoc(strength(area), nullptr, &best, nullptr, &at);
      if (best < floor) continue;
      const cv::Point2f pixel(std::min(2.0f * (area.x + at.x) + 0.5f, grey.cols - 1.0f),
                              std::min(2.0f * (area.y + at.y) + 0.5f, grey.rows - 1.0f));
      tracks_.push_back({pixel, cv::Point2f(0, 0), 0, 0});
      points_.push_back({pixel, false, false, 0});
    }
}

}  // namespace adugs::tracking

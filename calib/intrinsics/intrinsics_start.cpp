#include "calib/intrinsics/intrinsics_start.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "calib/intrinsics/intrinsics_problem.h"
#include "calib/solver_outcome.h"

namespace adugs::calib {
namespace {

// f^2 = -(x_a x_b + y_a y_b) / (w_a w_b) for two vanishing points of orthogonal directions.
bool focalFromOrthogonalPair(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double& f) {
  const double den = a.z() * b.z();
  const double num = -(a.x() * b.x() + a.y() * b.y());
  if (!(std::abs(den) > 0)) return false;
  const double f2 = num / den;
  if (!(f2 > 0) || !std::isfinite(f2)) return false;
  f = std::sqrt(f2);
  return true;
}

bool homographyOf(const TargetObservation& view, double cu, double cv, Eigen::Matrix3d& H) {
  std::vector<cv::Point2d> src, dst;
  for (const auto& c : view.corners) {
    src.emplace_back(c.point.x(), c.point.y());
    dst.emplace_back(c.pixel.x() - cu, c.pixel.y() - cv);
  }
  if (src.size() < 4) return false;
  const cv::Mat h = cv::findHomography(src, dst, 0);
  if (h.empty()) return false;
  cv::cv2eigen(h, H);
  return H.allFinite();
}

}  // namespace

std::vector<double> focalCandidatesFromHomography(const Eigen::Matrix3d& H) {
  std::vector<double> out;
  const Eigen::Vector3d h1 = H.col(0), h2 = H.col(1);
  double f = 0;
  if (focalFromOrthogonalPair(h1, h2, f)) out.push_back(f);            // rows and columns
  if (focalFromOrthogonalPair(h1 + h2, h1 - h2, f)) out.push_back(f);  // the two diagonals
  return out;
}

double scoreFocal(const std::vector<const TargetObservation*>& views, DistortionModel model,
                  double f, double cu, double cv, double* k1_out, int threads) {
  CalibCamera camera;
  camera.model = model;
  camera.params = {f, f, cu, cv, 0, 0, 0, 0};
  CameraBlocks b(camera);
  std::vector<Pose6> poses(views.size());
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ceres::SubsetManifold first_only(4, {1, 2, 3});
  for (size_t i = 0; i < views.size(); ++i) {
    if (!poseFromPnp(*views[i], f, cu, cv, poses[i])) continue;
    for (const auto& c : views[i]->corners)
      problem.AddResidualBlock(ReprojectionCost::create(camera, c), new ceres::HuberLoss(2.0),
                               b.focal, b.pp, b.q, b.dist, poses[i].data());
  }
  if (problem.NumResidualBlocks() == 0) return std::numeric_limits<double>::infinity();
  problem.SetParameterBlockConstant(b.focal);
  problem.SetParameterBlockConstant(b.pp);
  problem.SetParameterBlockConstant(b.q);
  problem.SetManifold(b.dist, &first_only);
  ceres::Solver::Options so = quietSolverOptions();
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = 30;
  so.function_tolerance = 1e-6;
  so.num_threads = threads;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable()) return std::numeric_limits<double>::infinity();
  if (k1_out) *k1_out = b.dist[0];
  return std::sqrt(2 * summary.final_cost / problem.NumResiduals());
}

FocalStart findFocalStart(const std::vector<const TargetObservation*>& all_views, int width,
                          int height, DistortionModel model, const FocalStartOptions& o) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("findFocalStart: bad image size");
  std::vector<const TargetObservation*> views;
  for (const TargetObservation* v : all_views)
    if (v && v->corners.size() >= 4) views.push_back(v);
  if (views.empty()) throw std::invalid_argument("findFocalStart: no view with 4 corners");
  const double cu = (width - 1) / 2.0, cv = (height - 1) / 2.0;
  const double lo = o.min_focal_over_width * width, hi = o.max_focal_over_width * width;
  constexpr double kLadder = 1.25;

  // Candidates from the views: sorted, near-duplicates (within 2 %) merged, evenly spread
  // quantiles kept.
  std::vector<double> from_views;
  for (const TargetObservation* v : views) {
    Eigen::Matrix3d H;
    if (!homographyOf(*v, cu, cv, H)) continue;
    for (double f : focalCandidatesFromHomography(H))
      if (f >= lo && f <= hi) from_views.push_back(f);
  }
  FocalStart start;
  start.view_candidates = static_cast<int>(from_views.size());
  std::sort(from_views.begin(), from_views.end());
  std::vector<double> distinct;
  for (double f : from_views)
    if (distinct.empty() || f > 1.02 * distinct.back()) distinct.push_back(f);
  std::vector<double> candidates;
  const size_t keep = static_cast<size_t>(std::max(1, o.max_candidates));
  if (distinct.size() <= keep) {
    candidates = distinct;
  } else {
    for (size_t k = 0; k < keep; ++k)
      candidates.push_back(distinct[(k * (distinct.size() - 1) + (keep - 1) / 2) / (keep - 1)]);
  }
  for (double f = lo; f <= hi * 1.0001; f *= kLadder) candidates.push_back(f);

  std::vector<const TargetObservation*> scored;
  const size_t n = views.size(), m = static_cast<size_t>(std::max(1, o.max_views_scored));
  if (n <= m) {
    scored = views;
  } else {
    for (size_t k = 0; k < m; ++k) scored.push_back(views[k * n / m]);
  }
  start.views_scored = static_cast<int>(scored.size());
  start.score_px = std::numeric_limits<double>::infinity();
  start.focal_px = std::clamp(0.5 * width, lo, hi);
  auto score = [&](double f) {
    double k1 = 0;
    const double s = scoreFocal(scored, model, f, cu, cv, &k1, o.threads);
    ++start.candidates_scored;
    if (s < start.score_px) {
      start.score_px = s;
      start.focal_px = f;
      start.first_distortion = k1;
    }
    return s;
  };
  for (double f : candidates) score(f);

  // Golden-section search in log f within one ladder step of the best candidate.
  if (std::isfinite(start.score_px)) {
    const double g = (std::sqrt(5.0) - 1) / 2;
    double a = std::log(std::max(lo, start.focal_px / kLadder));
    double b = std::log(std::min(hi, start.focal_px * kLadder));
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double s1 = score(std::exp(x1)), s2 = score(std::exp(x2));
    for (int it = 0; it < 6; ++it) {
      if (s1 < s2) {
        b = x2, x2 = x1, s2 = s1;
        x1 = b - g * (b - a);
        s1 = score(std::exp(x1));
      } else {
        a = x1, x1 = x2, s1 = s2;
        x2 = a + g * (b - a);
        s2 = score(std::exp(x2));
      }
    }
  }
  return start;
}

DistortionModel startDistortion(const CalibCamera& camera) {
  return camera.projection == ProjectionModel::kPinhole ? camera.model : DistortionModel::kEquidistant;
}

CalibCamera startCamera(const CalibCamera& model, int width, int height, const FocalStart& start) {
  const double f = start.focal_px;
  CalibCamera c;
  c.width = width;
  c.height = height;
  c.projection = model.projection;
  c.model = model.model;
  c.params = {f, f, (width - 1) / 2.0, (height - 1) / 2.0, 0, 0, 0, 0};
  switch (model.projection) {
    case ProjectionModel::kPinhole:
      c.params[4] = start.first_distortion;
      break;
    case ProjectionModel::kUnified:
      // Kalibr's start: xi = 1 (the paraboloid mirror); the on-axis focal length is fu / (1 + xi).
      c.projection_params = {1.0, 0.0};
      c.params[0] = c.params[1] = 2 * f;
      break;
    case ProjectionModel::kDoubleSphere:
      // Basalt's start: xi -0.2 (a lens with less than a hemisphere in view), alpha 0.5; the
      // on-axis focal length is fx / (1 + xi).
      // (From xi 0.3 the EuRoC cam0 views end in a second, slightly worse minimum at xi 0.81,
      // fu 836 px; from -0.5 and -0.2 in the same one, xi -0.29.)
      c.projection_params = {-0.2, 0.5};
      c.params[0] = c.params[1] = 0.8 * f;
      break;
    case ProjectionModel::kExtendedUnified:
      // Basalt's start: alpha 0.5, beta 1 (the unified model with xi = 1); on-axis focal fx.
      c.projection_params = {0.5, 1.0};
      break;
  }
  return c;
}

}  // namespace adugs::calib

#include "calib/intrinsics/intrinsics_calibrator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include "calib/intrinsics/intrinsics_problem.h"
#include "calib/solver_outcome.h"
#include "calib/text_format.h"
#include "data/camera_model.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace {

struct View {
  const TargetObservation* obs = nullptr;
  Pose6 pose{};              // target -> camera
  std::vector<bool> usable;  // false: too close to the image border (never used)
  std::vector<bool> inlier;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(n), v.end());
  return v[n];
}

const char* stageName(IntrinsicsStage stage) {
  switch (stage) {
    case IntrinsicsStage::kFocal:
      return "focal (+ first lens parameter, principal point at the centre)";
    case IntrinsicsStage::kPrincipalPoint: return "principal point";
    case IntrinsicsStage::kDistortion: return "distortion";
  }
  return "";
}

// The first lens parameter, freed with the focal length in stages 1-2 (CalibCamera index): the
// pinhole's k1; omni's xi (its distortion waits for stage 3); the double sphere's alpha (xi waits:
// with xi fixed the model is the unified one, which alpha alone already bends); EUCM's alpha (beta
// waits at 1: the unified model again).
int firstLensParameter(const CalibCamera& c) {
  switch (c.projection) {
    case ProjectionModel::kPinhole: return 4;
    case ProjectionModel::kUnified: return 8;
    case ProjectionModel::kDoubleSphere: return 9;
    case ProjectionModel::kExtendedUnified: return 8;
  }
  return 4;
}

bool freeInStage(const CalibCamera& c, IntrinsicsStage stage, int i) {
  if (!c.hasParameter(i)) return false;
  if (stage == IntrinsicsStage::kDistortion || i < 2) return true;
  if (i < 4) return stage == IntrinsicsStage::kPrincipalPoint;
  return i == firstLensParameter(c);
}

// Holds what the stage does not free: the whole block constant, or a SubsetManifold over the
// entries held. first = the block's first CalibCamera index.
void holdFixed(ceres::Problem& problem, double* block, int size, int first, const CalibCamera& c,
               IntrinsicsStage stage) {
  std::vector<int> fixed;
  for (int k = 0; k < size; ++k)
    if (!freeInStage(c, stage, first + k)) fixed.push_back(k);
  if (static_cast<int>(fixed.size()) == size) problem.SetParameterBlockConstant(block);
  else if (!fixed.empty()) problem.SetManifold(block, new ceres::SubsetManifold(size, fixed));
}

// The projection parameters' ranges (data::CameraModel's): omni xi >= 0; ds xi in [-1, 1], alpha
// in [0, 1]; eucm alpha in [0, 1], beta > 0.
void boundProjection(ceres::Problem& problem, double* q, ProjectionModel projection) {
  auto bound = [&](int k, double lo, double hi) {
    problem.SetParameterLowerBound(q, k, lo);
    if (std::isfinite(hi)) problem.SetParameterUpperBound(q, k, hi);
  };
  const double inf = std::numeric_limits<double>::infinity();
  switch (projection) {
    case ProjectionModel::kPinhole: break;
    case ProjectionModel::kUnified: bound(0, 0, inf); break;
    case ProjectionModel::kDoubleSphere: bound(0, -1, 1), bound(1, 0, 1); break;
    case ProjectionModel::kExtendedUnified: bound(0, 0, 1), bound(1, 1e-6, inf); break;
  }
}

}  // namespace

void readIntrinsicsOptions(data::YamlOptionsReader& r, IntrinsicsOptions& o) {
  std::string model;
  if (r.optional("distortion_model", model)) {
    o.projection = ProjectionModel::kPinhole;
    // 'none' is no lens to calibrate: this calibration estimates a distortion.
    r.check(data::parseDistortionModel(model, o.model) && o.model != data::DistortionModel::kNone,
            "distortion_model", "unknown distortion model '" + model + "' (use radtan or equidistant)");
  }
  r.optional("min_views", o.min_views, 1, 100000);
  r.optional("min_corners_per_view", o.min_corners_per_view, 4, 100000);
  r.optional("outlier_sigma", o.outlier_sigma, 0.0, 100.0);
  r.optional("max_outlier_rounds", o.max_outlier_rounds, 0, 100);
  r.optional("max_iterations", o.max_iterations, 1, 100000);
  r.optional("threads", o.threads, 1, 256);
  r.optional("initial_focal_px", o.initial_focal_px, 0.0, 1e6);
  r.optional("min_focal_over_width", o.min_focal_over_width, 0.01, 100.0);
  r.optional("max_focal_over_width", o.max_focal_over_width, 0.01, 100.0);
  r.optional("compute_covariance", o.compute_covariance);
  r.optional("min_border_distance_px", o.min_border_distance_px, 0.0, 1e4);
}

IntrinsicsResult calibrateIntrinsics(const std::vector<TargetObservation>& observations,
                                     int width, int height, const IntrinsicsOptions& options) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("calibrateIntrinsics: image size must be positive");
  const auto t0 = std::chrono::steady_clock::now();
  IntrinsicsResult result;
  result.views_given = static_cast<int>(observations.size());
  const double cu = (width - 1) / 2.0, cv0 = (height - 1) / 2.0;
  const double f_min = options.min_focal_over_width * width;
  const double f_max = options.max_focal_over_width * width;
  if (!(f_min > 0 && f_max > f_min))
    throw data::InputError("", 0, "min_focal_over_width",
                           "the plausible focal range [min_focal_over_width, "
                           "max_focal_over_width] x width must be positive and not empty");

  std::vector<View> views;
  for (const auto& obs : observations) {
    if (static_cast<int>(obs.corners.size()) < std::max(4, options.min_corners_per_view)) continue;
    View v;
    v.obs = &obs;
    v.usable.assign(obs.corners.size(), true);
    const double d = options.min_border_distance_px;
    for (size_t i = 0; i < obs.corners.size() && d > 0; ++i) {
      const Eigen::Vector2d& p = obs.corners[i].pixel;
      if (p.x() < d || p.y() < d || p.x() > width - 1 - d || p.y() > height - 1 - d) {
        v.usable[i] = false;
        ++result.border_excluded;
      }
    }
    v.inlier = v.usable;
    views.push_back(v);
  }
  auto tooFew = [&](const std::string& what) {
    throw data::InputError("", 0, "views",
                           what + ": " + std::to_string(views.size()) + " usable of " +
                               std::to_string(observations.size()) + " views (a view needs >= " +
                               std::to_string(options.min_corners_per_view) +
                               " corners); at least " + std::to_string(options.min_views) +
                               " are needed");
  };
  if (static_cast<int>(views.size()) < std::max(1, options.min_views))
    tooFew("too few views with enough target corners");

  // The start: a focal length for a distortion-free pinhole with the principal point at the
  // centre, never outside the plausible range.
  double f = options.initial_focal_px;
  if (f > 0) {
    if (f < f_min || f > f_max)
      throw data::InputError("", 0, "initial_focal_px",
                             strprintf("%.1f px is outside the plausible range [%.1f, %.1f] px "
                                       "(%.2g..%.2g x the image width)",
                                       f, f_min, f_max, options.min_focal_over_width,
                                       options.max_focal_over_width));
  } else {
    std::vector<const TargetObservation*> obs;
    for (const View& v : views) obs.push_back(v.obs);
    FocalStartOptions so;
    so.min_focal_over_width = options.min_focal_over_width;
    so.max_focal_over_width = options.max_focal_over_width;
    so.threads = options.threads;
    if (options.progress) options.progress("start: scoring focal lengths");
    const auto ts = std::chrono::steady_clock::now();
    CalibCamera model;
    model.projection = options.projection;
    model.model = options.model;
    result.focal_start = findFocalStart(obs, width, height, startDistortion(model), so);
    f = result.focal_start.focal_px;
    result.start_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
  }
  result.initial_focal_px = f;

  std::vector<View> posed;
  for (View& v : views)
    if (poseFromPnp(*v.obs, f, cu, cv0, v.pose)) posed.push_back(v);
  views = std::move(posed);
  if (static_cast<int>(views.size()) < std::max(1, options.min_views))
    tooFew("too few views with a valid initial pose");

  CalibCamera cam;
  cam.projection = options.projection;
  cam.model = options.model;
  FocalStart start = result.focal_start;
  start.focal_px = f;
  if (options.initial_focal_px > 0) start.first_distortion = 0;
  cam = startCamera(cam, width, height, start);
  result.start_camera = cam;
  const CameraBlocks b(cam);

  // One solve of the current stage over the current inliers. Bounds keep the focal length in the
  // plausible range and the principal point in the image (a result on a bound fails the verdict).
  auto solve = [&](IntrinsicsStage stage, bool robust) {
    if (options.progress)
      options.progress(strprintf("stage %d/3, %s, %zu views", static_cast<int>(stage) + 1,
                                 stageName(stage), views.size()));
    ceres::Problem problem;
    for (View& v : views)
      for (size_t i = 0; i < v.obs->corners.size(); ++i)
        if (v.inlier[i])
          problem.AddResidualBlock(ReprojectionCost::create(cam, v.obs->corners[i]),
                                   robust ? new ceres::HuberLoss(2.0) : nullptr, b.focal, b.pp,
                                   b.q, b.dist, v.pose.data());
    if (problem.NumResidualBlocks() == 0) return;
    for (int k = 0; k < 2; ++k) {
      problem.SetParameterLowerBound(b.focal, k, f_min);
      problem.SetParameterUpperBound(b.focal, k, f_max);
    }
    problem.SetParameterLowerBound(b.pp, 0, 0);
    problem.SetParameterUpperBound(b.pp, 0, width - 1);
    problem.SetParameterLowerBound(b.pp, 1, 0);
    problem.SetParameterUpperBound(b.pp, 1, height - 1);
    boundProjection(problem, b.q, cam.projection);
    holdFixed(problem, b.pp, 2, 2, cam, stage);
    holdFixed(problem, b.dist, 4, 4, cam, stage);
    holdFixed(problem, b.q, 2, 8, cam, stage);
    ceres::Solver::Options so = quietSolverOptions();
    so.linear_solver_type = ceres::DENSE_SCHUR;
    // Stages 1-2 only prepare the start of the next one: on views that do not fix the focal
    // length their cost is flat along it and they would use every iteration allowed.
    so.max_num_iterations = stage == IntrinsicsStage::kDistortion
                                ? options.max_iterations
                                : std::max(1, options.max_iterations / 4);
    so.num_threads = options.threads;
    // The Huber solves only prepare the next solve: converged to 1e-6 is close enough. The plain
    // least-squares solves of the last stage give the result: to 1e-10.
    so.function_tolerance = robust ? 1e-6 : 1e-10;
    so.parameter_tolerance = robust ? 1e-6 : 1e-10;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result.iterations += static_cast<int>(summary.iterations.size());
    ++result.solves;
    const SolverOutcome outcome = describeSolve(summary);
    result.final_solve_usable = outcome.usable;
    result.final_solve_converged = outcome.converged;
    if (!outcome.usable)
      result.solver_problems.push_back(std::string(stageName(stage)) + " stage: " + outcome.problem);
    if (std::getenv("ADUGS_CALIB_DEBUG"))
      std::fprintf(stderr, "%s: %s\n", stageName(stage), summary.BriefReport().c_str());
  };

  // Corners whose residual exceeds k sigma (either axis) leave the inlier set; a corner behind
  // the camera always does. sigma <= 0: measured now, per axis, over the candidates.
  auto reject = [&](double sigma, bool readmit) {
    int removed = 0;
    for (View& v : views)
      for (size_t i = 0; i < v.obs->corners.size(); ++i) {
        if (!v.usable[i] || (!readmit && !v.inlier[i])) continue;
        const Eigen::Vector2d r = cornerResidual(cam, v.pose, v.obs->corners[i]);
        const bool in = r.allFinite() && r.cwiseAbs().maxCoeff() <= options.outlier_sigma * sigma;
        removed += v.inlier[i] && !in;
        v.inlier[i] = in;
      }
    return removed;
  };
  auto candidateResiduals = [&](bool robust_sigma) {
    std::vector<double> axis;
    double sum_sq = 0;
    for (const View& v : views)
      for (size_t i = 0; i < v.obs->corners.size(); ++i) {
        if (!v.usable[i]) continue;
        const Eigen::Vector2d r = cornerResidual(cam, v.pose, v.obs->corners[i]);
        if (!r.allFinite()) continue;
        axis.push_back(std::abs(r.x()));
        axis.push_back(std::abs(r.y()));
        sum_sq += r.squaredNorm();
      }
    if (axis.empty()) return 0.0;
    // Floor: on exact (synthetic, noise-free) corners sigma is ~1e-10 px and "3 sigma" would
    // reject corners for rounding; no real detector is better than 0.01 px.
    constexpr double kMinSigmaPx = 0.01;
    return std::max(kMinSigmaPx, robust_sigma ? 1.4826 * median(axis) : std::sqrt(sum_sq / axis.size()));
  };
  // A view left with too few corners cannot hold its pose.
  auto dropThinViews = [&]() {
    views.erase(std::remove_if(views.begin(), views.end(),
                               [](const View& v) {
                                 return std::count(v.inlier.begin(), v.inlier.end(), true) < 6;
                               }),
                views.end());
    if (static_cast<int>(views.size()) < std::max(1, options.min_views))
      tooFew("too few views left after outlier rejection");
  };
  auto recordStage = [&](IntrinsicsStage stage, int outliers) {
    IntrinsicsStageResult sr;
    sr.stage = stage;
    sr.camera = cam;
    sr.outliers = outliers;
    result.stages.push_back(sr);
  };

  // Stages 1 and 2 (focal + k1; + principal point): every usable corner, Huber loss, then
  // corners beyond outlier_sigma robust sigmas (1.4826 MAD: the distortion these stages cannot
  // model widens the distribution without letting a gross error hide) are left out of a second
  // solve. Each stage starts again from every usable corner, so the corners a simpler model
  // could not fit are judged again by the next one. Stage 1 frees the first distortion
  // coefficient with the focal length: held at 0, the focal length of EuRoC cam0 ran from 460 to
  // 1600 px on the face-on cam_april views and the principal point to the image border.
  for (IntrinsicsStage stage : {IntrinsicsStage::kFocal, IntrinsicsStage::kPrincipalPoint}) {
    for (View& v : views) v.inlier = v.usable;
    solve(stage, true);
    int removed = 0;
    if (options.outlier_sigma > 0) {
      removed = reject(candidateResiduals(true), true);
      if (removed > 0) solve(stage, true);
    }
    recordStage(stage, removed);
  }

  // Stage 3 (distortion): every usable corner again, Huber then plain least squares, then
  // outlier rounds. sigma is the per-axis standard deviation of the residuals of the first
  // plain solution (the classic 3-sigma rule, as Kalibr). It is not re-measured on the
  // survivors: that would shrink it every round and eat into the tails of a good error
  // distribution (a median-based sigma does the same: far, foreshortened corners are
  // legitimately noisier).
  for (View& v : views) v.inlier = v.usable;
  solve(IntrinsicsStage::kDistortion, true);
  solve(IntrinsicsStage::kDistortion, false);
  result.camera_all_corners = cam;
  const double sigma = candidateResiduals(false);
  for (int round = 0; options.outlier_sigma > 0 && round < options.max_outlier_rounds; ++round) {
    if (!(sigma > 0)) break;
    const int removed = reject(sigma, false);
    if (removed == 0) break;
    result.outliers += removed;
    result.outlier_rounds = round + 1;
    dropThinViews();
    solve(IntrinsicsStage::kDistortion, false);
  }
  recordStage(IntrinsicsStage::kDistortion, result.outliers);

  // Statistics and residuals.
  double sum2 = 0, sum = 0;
  Eigen::Vector2d sum_axis2 = Eigen::Vector2d::Zero();
  int n = 0;
  for (size_t vi = 0; vi < views.size(); ++vi) {
    const View& v = views[vi];
    ViewStats vs;
    vs.t_ns = v.obs->t_ns;
    vs.source = v.obs->source;
    vs.corners = static_cast<int>(v.obs->corners.size());
    Eigen::Vector3d aa(v.pose[0], v.pose[1], v.pose[2]);
    const double angle = aa.norm();
    vs.T_C_T.linear() = angle > 0 ? Eigen::AngleAxisd(angle, aa / angle).toRotationMatrix()
                                  : Eigen::Matrix3d::Identity();
    vs.T_C_T.translation() = Eigen::Vector3d(v.pose[3], v.pose[4], v.pose[5]);
    double view_sum2 = 0;
    for (size_t i = 0; i < v.obs->corners.size(); ++i) {
      const auto& c = v.obs->corners[i];
      CornerResidual cr;
      cr.view = static_cast<int>(vi);
      cr.tag_id = c.tag_id;
      cr.corner = c.corner;
      cr.pixel = c.pixel;
      cr.residual = cornerResidual(cam, v.pose, c);
      cr.inlier = v.inlier[i];
      result.residuals.push_back(cr);
      if (!cr.inlier) continue;
      if (!cr.residual.allFinite()) {
        ++result.corners_not_projected;
        continue;
      }
      const double e2 = cr.residual.squaredNorm();
      view_sum2 += e2;
      sum2 += e2;
      sum += std::sqrt(e2);
      sum_axis2 += cr.residual.cwiseAbs2();
      result.max_px = std::max(result.max_px, std::sqrt(e2));
      ++vs.inliers;
      ++n;
    }
    vs.rms_px = vs.inliers > 0 ? std::sqrt(view_sum2 / vs.inliers) : 0;
    result.views.push_back(vs);
  }
  result.views_skipped = result.views_given - static_cast<int>(views.size());
  result.corners_used = n;
  if (n > 0) {
    result.rms_px = std::sqrt(sum2 / n);
    result.mean_px = sum / n;
    result.std_px = (sum_axis2 / n).cwiseSqrt();
  } else {
    result.rms_px = result.mean_px = result.max_px = std::numeric_limits<double>::quiet_NaN();
  }

  if (options.compute_covariance && result.final_solve_usable && n > 0) {
    if (options.progress) options.progress("covariance");
    // Covariance of the intrinsics with the poses marginalised: the Schur complement
    // S = Hii - sum_v Hip Hpp^-1 Hpi of J'J, built view by view from the evaluated Jacobian
    // (much faster than a dense covariance over every pose). Its columns are CalibCamera's
    // parameter indices (focal, pp, distortion, projection); those the model does not have are
    // left out of the inverse.
    constexpr int kI = CalibCamera::kParameters;
    using MatrixI = Eigen::Matrix<double, kI, kI>;
    ceres::Problem problem;
    std::vector<double*> blocks = {b.focal, b.pp, b.dist, b.q};
    for (View& v : views) {
      blocks.push_back(v.pose.data());
      for (size_t i = 0; i < v.obs->corners.size(); ++i)
        if (v.inlier[i])
          problem.AddResidualBlock(ReprojectionCost::create(cam, v.obs->corners[i]), nullptr,
                                   b.focal, b.pp, b.q, b.dist, v.pose.data());
    }
    std::vector<int> used;
    for (int i = 0; i < kI; ++i)
      if (cam.hasParameter(i)) used.push_back(i);
    const int m = static_cast<int>(used.size());
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = blocks;
    eo.num_threads = options.threads;
    ceres::CRSMatrix J;
    const int dof = 2 * n - m - 6 * static_cast<int>(views.size());
    if (dof > 0 && problem.Evaluate(eo, nullptr, nullptr, nullptr, &J)) {
      MatrixI S = MatrixI::Zero();
      std::vector<Eigen::Matrix<double, kI, 6>> Hip(views.size(), Eigen::Matrix<double, kI, 6>::Zero());
      std::vector<Eigen::Matrix<double, 6, 6>> Hpp(views.size(), Eigen::Matrix<double, 6, 6>::Zero());
      for (int row = 0; row < J.num_rows; ++row) {
        Eigen::Matrix<double, kI, 1> a = Eigen::Matrix<double, kI, 1>::Zero();
        Eigen::Matrix<double, 6, 1> p = Eigen::Matrix<double, 6, 1>::Zero();
        int view = -1;
        for (int k = J.rows[row]; k < J.rows[row + 1]; ++k) {
          const int col = J.cols[k];
          if (col < kI) {
            a(col) = J.values[k];
          } else {
            view = (col - kI) / 6;
            p((col - kI) % 6) = J.values[k];
          }
        }
        S += a * a.transpose();
        if (view >= 0) {
          Hip[view] += a * p.transpose();
          Hpp[view] += p * p.transpose();
        }
      }
      for (size_t v = 0; v < views.size(); ++v)
        S -= Hip[v] * Hpp[v].ldlt().solve(Hip[v].transpose());
      Eigen::MatrixXd S_used(m, m);
      for (int r = 0; r < m; ++r)
        for (int c = 0; c < m; ++c) S_used(r, c) = S(used[r], used[c]);
      const Eigen::MatrixXd cov_used = S_used.inverse() * (sum2 / dof);
      if (cov_used.allFinite()) {
        result.covariance.setZero();
        for (int r = 0; r < m; ++r)
          for (int c = 0; c < m; ++c) result.covariance(used[r], used[c]) = cov_used(r, c);
        for (int i = 0; i < kI; ++i) result.sigma[i] = std::sqrt(std::max(0.0, result.covariance(i, i)));
        result.has_sigma = true;
      }
    }
  }

  result.camera = cam;
  result.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

double reprojectionRmsWithFixedIntrinsics(const std::vector<TargetObservation>& views,
                                          const CalibCamera& camera, int min_corners) {
  CalibCamera cam = camera;
  double sum2 = 0;
  size_t n = 0;
  for (const auto& obs : views) {
    if (static_cast<int>(obs.corners.size()) < std::max(4, min_corners)) continue;
    // Initial pose from the undistorted rays (model-agnostic), then refine with the model.
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> normalised;
    for (const auto& c : obs.corners) {
      Eigen::Vector3d ray;
      if (!cam.unproject(c.pixel, ray)) continue;
      object.emplace_back(c.point.x(), c.point.y(), c.point.z());
      normalised.emplace_back(ray.x(), ray.y());
    }
    if (object.size() < 4) continue;
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(object, normalised, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec,
                      false, cv::SOLVEPNP_ITERATIVE))
      continue;
    std::array<double, 6> pose;
    for (int i = 0; i < 3; ++i) {
      pose[i] = rvec.at<double>(i);
      pose[3 + i] = tvec.at<double>(i);
    }
    ceres::Problem problem;
    const CameraBlocks b(cam);
    for (const auto& c : obs.corners)
      problem.AddResidualBlock(ReprojectionCost::create(cam, c), nullptr, b.focal, b.pp, b.q,
                               b.dist, pose.data());
    for (double* block : {b.focal, b.pp, b.q, b.dist}) problem.SetParameterBlockConstant(block);
    ceres::Solver::Options so = quietSolverOptions();
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 50;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    for (const auto& c : obs.corners) {
      const Eigen::Vector2d r = cornerResidual(cam, pose, c);
      if (!r.allFinite()) continue;  // behind the camera
      sum2 += r.squaredNorm();
      ++n;
    }
  }
  return n > 0 ? std::sqrt(sum2 / n) : -1;
}

}  // namespace adugs::calib

#include "calib/intrinsics_calibrator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include "data/camera_model.h"
#include "data/input_error.h"
#include "data/yaml_options.h"

namespace adugs::calib {
namespace {

struct ReprojectionCost {
  ReprojectionCost(DistortionModel model, const Eigen::Vector2d& pixel, const Eigen::Vector3d& p_T)
      : model_(model), pixel_(pixel), p_T_(p_T) {}

  template <typename T>
  bool operator()(const T* proj, const T* dist, const T* pose, T* residual) const {
    const T p[3] = {T(p_T_.x()), T(p_T_.y()), T(p_T_.z())};
    T p_C[3];
    ceres::AngleAxisRotatePoint(pose, p, p_C);
    for (int i = 0; i < 3; ++i) p_C[i] += pose[3 + i];
    T params[8] = {proj[0], proj[1], proj[2], proj[3], dist[0], dist[1], dist[2], dist[3]};
    T uv[2];
    if (!data::projectPoint(model_, params, p_C, uv)) return false;
    residual[0] = uv[0] - T(pixel_.x());
    residual[1] = uv[1] - T(pixel_.y());
    return true;
  }

  DistortionModel model_;
  Eigen::Vector2d pixel_;
  Eigen::Vector3d p_T_;
};

struct View {
  const TargetObservation* obs = nullptr;
  std::array<double, 6> pose{};  // angle-axis, translation (target -> camera)
  std::vector<bool> inlier;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(n), v.end());
  return v[n];
}

// One focal length per view from H = K [r1 r2 t] with K = diag(f, f, 1) in coordinates centred
// on the image centre: h1' B h2 = 0 and h1' B h1 = h2' B h2 with B = diag(a, a, 1), a = 1/f^2.
double focalFromHomographies(const std::vector<View>& views, double cu, double cv) {
  std::vector<double> focals;
  for (const View& v : views) {
    std::vector<cv::Point2d> src, dst;
    for (const auto& c : v.obs->corners) {
      src.emplace_back(c.point.x(), c.point.y());
      dst.emplace_back(c.pixel.x() - cu, c.pixel.y() - cv);
    }
    const cv::Mat H = cv::findHomography(src, dst, 0);
    if (H.empty()) continue;
    auto h = [&](int r, int c) { return H.at<double>(r, c); };
    const double A1 = h(0, 0) * h(0, 1) + h(1, 0) * h(1, 1), C1 = h(2, 0) * h(2, 1);
    const double A2 = h(0, 0) * h(0, 0) - h(0, 1) * h(0, 1) + h(1, 0) * h(1, 0) - h(1, 1) * h(1, 1);
    const double C2 = h(2, 0) * h(2, 0) - h(2, 1) * h(2, 1);
    const double den = A1 * A1 + A2 * A2;
    if (!(den > 0)) continue;
    const double a = -(A1 * C1 + A2 * C2) / den;
    // A nearly fronto-parallel view carries no focal information (C1, C2 ~ 0): skip it.
    const double info = std::sqrt(C1 * C1 + C2 * C2) / std::sqrt(den);
    if (a > 0 && info > 1e-8) focals.push_back(1.0 / std::sqrt(a));
  }
  return median(focals);
}

bool solvePose(const TargetObservation& obs, double f, double cu, double cv,
               std::array<double, 6>& pose) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto& c : obs.corners) {
    object.emplace_back(c.point.x(), c.point.y(), c.point.z());
    image.emplace_back(c.pixel.x(), c.pixel.y());
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << f, 0, cu, 0, f, cv, 0, 0, 1);
  cv::Mat rvec, tvec;
  bool planar = std::all_of(obs.corners.begin(), obs.corners.end(),
                            [](const CornerObservation& c) { return std::abs(c.point.z()) < 1e-9; });
  if (!cv::solvePnP(object, image, K, cv::noArray(), rvec, tvec, false,
                    planar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_ITERATIVE))
    return false;
  if (!(tvec.at<double>(2) > 0)) return false;
  for (int i = 0; i < 3; ++i) {
    pose[i] = rvec.at<double>(i);
    pose[3 + i] = tvec.at<double>(i);
  }
  return std::all_of(pose.begin(), pose.end(), [](double x) { return std::isfinite(x); });
}

Eigen::Vector2d residualOf(const PinholeCamera& cam, const std::array<double, 6>& pose,
                           const CornerObservation& c) {
  ReprojectionCost cost(cam.model, c.pixel, c.point);
  Eigen::Vector2d r;
  if (!cost(cam.params.data(), cam.params.data() + 4, pose.data(), r.data()))
    return Eigen::Vector2d::Constant(1e6);
  return r;
}

}  // namespace

void readIntrinsicsOptions(data::YamlOptionsReader& r, IntrinsicsOptions& o) {
  std::string model;
  if (r.optional("distortion_model", model)) {
    r.check(data::parseDistortionModel(model, o.model), "distortion_model",
            "unknown distortion model '" + model + "' (use radtan or equidistant)");
  }
  r.optional("min_views", o.min_views, 1, 100000);
  r.optional("min_corners_per_view", o.min_corners_per_view, 4, 100000);
  r.optional("outlier_sigma", o.outlier_sigma, 0.0, 100.0);
  r.optional("max_outlier_rounds", o.max_outlier_rounds, 0, 100);
  r.optional("max_iterations", o.max_iterations, 1, 100000);
  r.optional("threads", o.threads, 1, 256);
  r.optional("initial_focal_px", o.initial_focal_px, 0.0, 1e6);
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

  std::vector<View> views;
  for (const auto& obs : observations) {
    if (static_cast<int>(obs.corners.size()) < std::max(4, options.min_corners_per_view)) continue;
    View v;
    v.obs = &obs;
    v.inlier.assign(obs.corners.size(), true);
    const double d = options.min_border_distance_px;
    for (size_t i = 0; i < obs.corners.size() && d > 0; ++i) {
      const Eigen::Vector2d& p = obs.corners[i].pixel;
      if (p.x() < d || p.y() < d || p.x() > width - 1 - d || p.y() > height - 1 - d) {
        v.inlier[i] = false;
        ++result.border_excluded;
      }
    }
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

  double f = options.initial_focal_px;
  if (!(f > 0)) {
    // Candidates: the homography estimate (poor under strong distortion or with fronto-parallel
    // views) and fields of view from 30 to 150 degrees; keep the one whose distortion-free PnP
    // fits the corners best (median over views of the RMS error).
    std::vector<double> candidates;
    const double fh = focalFromHomographies(views, cu, cv0);
    if (fh > 0 && std::isfinite(fh)) candidates.push_back(fh);
    for (int fov = 30; fov <= 150; fov += 10)
      candidates.push_back(0.5 * width / std::tan(0.5 * fov * M_PI / 180.0));
    double best = 1e300;
    const size_t stride = std::max<size_t>(1, views.size() / 20);  // enough views to judge
    for (double fc : candidates) {
      PinholeCamera probe;
      probe.model = options.model;
      probe.params = {fc, fc, cu, cv0, 0, 0, 0, 0};
      std::vector<double> rms;
      for (size_t vi = 0; vi < views.size(); vi += stride) {
        std::array<double, 6> pose;
        if (!solvePose(*views[vi].obs, fc, cu, cv0, pose)) continue;
        double s2 = 0;
        for (const auto& c : views[vi].obs->corners) s2 += residualOf(probe, pose, c).squaredNorm();
        rms.push_back(std::sqrt(s2 / views[vi].obs->corners.size()));
      }
      const double m = median(rms);
      if (!rms.empty() && m < best) {
        best = m;
        f = fc;
      }
    }
  }
  if (!(f > 0) || !std::isfinite(f)) f = 0.5 * std::max(width, height);  // ~90 deg guess
  result.initial_focal_px = f;

  std::vector<View> posed;
  for (View& v : views)
    if (solvePose(*v.obs, f, cu, cv0, v.pose)) posed.push_back(v);
  views = std::move(posed);
  if (static_cast<int>(views.size()) < std::max(1, options.min_views))
    tooFew("too few views with a valid initial pose");

  PinholeCamera cam;
  cam.width = width;
  cam.height = height;
  cam.model = options.model;
  cam.params = {f, f, cu, cv0, 0, 0, 0, 0};

  auto solve = [&](bool fix_distortion, bool robust, int max_iterations) {
    ceres::Problem problem;
    for (View& v : views) {
      for (size_t i = 0; i < v.obs->corners.size(); ++i) {
        if (!v.inlier[i]) continue;
        const auto& c = v.obs->corners[i];
        auto* cost = new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 4, 6>(
            new ReprojectionCost(cam.model, c.pixel, c.point));
        problem.AddResidualBlock(cost, robust ? new ceres::HuberLoss(2.0) : nullptr,
                                 cam.params.data(), cam.params.data() + 4, v.pose.data());
      }
    }
    // Stage 1 frees only the first distortion coefficient (k1 for both models): it absorbs most
    // of a strong barrel distortion, so the focal length need not slide far to fit it.
    if (fix_distortion)
      problem.SetManifold(cam.params.data() + 4, new ceres::SubsetManifold(4, {1, 2, 3}));
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_SCHUR;
    so.max_num_iterations = max_iterations;
    so.num_threads = options.threads;
    so.function_tolerance = 1e-10;
    so.parameter_tolerance = 1e-10;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result.iterations += static_cast<int>(summary.iterations.size());
    if (std::getenv("ADUGS_CALIB_DEBUG")) std::fprintf(stderr, "%s\n", summary.BriefReport().c_str());
  };

  solve(/*fix_distortion=*/true, /*robust=*/true, options.max_iterations);
  solve(false, false, options.max_iterations);

  // Outlier rounds. sigma is the per-axis standard deviation of the residuals of the first
  // solution (the classic 3-sigma rule, as Kalibr). It is not re-measured on the survivors:
  // that would shrink it every round and eat into the tails of a good error distribution (a
  // median-based sigma does the same: far, foreshortened corners are legitimately noisier).
  double sigma = 0;
  for (int round = 0; options.outlier_sigma > 0 && round < options.max_outlier_rounds; ++round) {
    if (round == 0) {
      double sum_sq = 0;
      size_t count = 0;
      for (const View& v : views)
        for (size_t i = 0; i < v.obs->corners.size(); ++i)
          if (v.inlier[i]) {
            sum_sq += residualOf(cam, v.pose, v.obs->corners[i]).squaredNorm();
            count += 2;
          }
      sigma = count > 0 ? std::sqrt(sum_sq / count) : 0;
    }
    if (!(sigma > 0)) break;
    int removed = 0;
    for (View& v : views)
      for (size_t i = 0; i < v.obs->corners.size(); ++i)
        if (v.inlier[i] &&
            residualOf(cam, v.pose, v.obs->corners[i]).cwiseAbs().maxCoeff() >
                options.outlier_sigma * sigma) {
          v.inlier[i] = false;
          ++removed;
        }
    if (removed == 0) break;
    result.outliers += removed;
    result.outlier_rounds = round + 1;
    // A view left with too few corners cannot hold its pose.
    views.erase(std::remove_if(views.begin(), views.end(),
                               [](const View& v) {
                                 return std::count(v.inlier.begin(), v.inlier.end(), true) < 6;
                               }),
                views.end());
    if (static_cast<int>(views.size()) < std::max(1, options.min_views))
      tooFew("too few views left after outlier rejection");
    solve(false, false, options.max_iterations);
  }

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
      cr.residual = residualOf(cam, v.pose, c);
      cr.inlier = v.inlier[i];
      result.residuals.push_back(cr);
      if (!cr.inlier) continue;
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
  }

  if (options.compute_covariance) {
    // Covariance of the 8 intrinsics with the poses marginalised: the Schur complement
    // S = Hii - sum_v Hip Hpp^-1 Hpi of J'J, built view by view from the evaluated Jacobian
    // (much faster than a dense covariance over every pose).
    ceres::Problem problem;
    std::vector<double*> blocks = {cam.params.data(), cam.params.data() + 4};
    for (View& v : views) {
      blocks.push_back(v.pose.data());
      for (size_t i = 0; i < v.obs->corners.size(); ++i)
        if (v.inlier[i])
          problem.AddResidualBlock(
              new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 4, 6>(
                  new ReprojectionCost(cam.model, v.obs->corners[i].pixel,
                                       v.obs->corners[i].point)),
              nullptr, cam.params.data(), cam.params.data() + 4, v.pose.data());
    }
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = blocks;
    eo.num_threads = options.threads;
    ceres::CRSMatrix J;
    const int dof = 2 * n - 8 - 6 * static_cast<int>(views.size());
    if (dof > 0 && problem.Evaluate(eo, nullptr, nullptr, nullptr, &J)) {
      Eigen::Matrix<double, 8, 8> S = Eigen::Matrix<double, 8, 8>::Zero();
      std::vector<Eigen::Matrix<double, 8, 6>> Hip(views.size(), Eigen::Matrix<double, 8, 6>::Zero());
      std::vector<Eigen::Matrix<double, 6, 6>> Hpp(views.size(), Eigen::Matrix<double, 6, 6>::Zero());
      for (int row = 0; row < J.num_rows; ++row) {
        Eigen::Matrix<double, 8, 1> a = Eigen::Matrix<double, 8, 1>::Zero();
        Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
        int view = -1;
        for (int k = J.rows[row]; k < J.rows[row + 1]; ++k) {
          const int col = J.cols[k];
          if (col < 8) {
            a(col) = J.values[k];
          } else {
            view = (col - 8) / 6;
            b((col - 8) % 6) = J.values[k];
          }
        }
        S += a * a.transpose();
        if (view >= 0) {
          Hip[view] += a * b.transpose();
          Hpp[view] += b * b.transpose();
        }
      }
      for (size_t v = 0; v < views.size(); ++v)
        S -= Hip[v] * Hpp[v].ldlt().solve(Hip[v].transpose());
      const Eigen::Matrix<double, 8, 8> cov = S.inverse() * (sum2 / dof);
      if (cov.allFinite()) {
        for (int i = 0; i < 8; ++i) result.sigma[i] = std::sqrt(std::max(0.0, cov(i, i)));
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
                                          const PinholeCamera& camera, int min_corners) {
  PinholeCamera cam = camera;
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
    for (const auto& c : obs.corners)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 4, 6>(
                                   new ReprojectionCost(cam.model, c.pixel, c.point)),
                               nullptr, cam.params.data(), cam.params.data() + 4, pose.data());
    problem.SetParameterBlockConstant(cam.params.data());
    problem.SetParameterBlockConstant(cam.params.data() + 4);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 50;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    for (const auto& c : obs.corners) {
      sum2 += residualOf(cam, pose, c).squaredNorm();
      ++n;
    }
  }
  return n > 0 ? std::sqrt(sum2 / n) : -1;
}

}  // namespace adugs::calib

#include "calib/intrinsics/intrinsics_verdict.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "calib/text_format.h"
#include "data/formats/yaml_options.h"

namespace adugs::calib {
namespace {

constexpr double kDeg = 180.0 / M_PI;

constexpr int kParameters = CalibCamera::kParameters;


const std::string kMoreViews =
    "more views (30 or more) from different positions: near and far, left and right, above and "
    "below";
const std::string kTilt = "tilt the board by +-30 deg about both of its axes, some views at 45 deg";
const std::string kFill =
    "fill the image: move the board so its corners reach every part of the image, its corners "
    "and borders included";
const std::string kDetections =
    "check the detections (residuals.png and the largest corner residuals in report.txt): "
    "motion blur, a bent or glossy board, the wrong target";

}  // namespace

void readIntrinsicsVerdictOptions(data::YamlOptionsReader& r, IntrinsicsVerdictOptions& o) {
  r.optional("min_views", o.min_views, 1, 100000);
  r.optional("min_image_share", o.min_image_share, 0.0, 1.0);
  r.optional("min_tilt_spread_deg", o.min_tilt_spread_deg, 0.0, 180.0);
  r.optional("max_focal_rel_sigma", o.max_focal_rel_sigma, 0.0, 10.0);
  r.optional("max_principal_point_rel_sigma", o.max_principal_point_rel_sigma, 0.0, 10.0);
  r.optional("max_distortion_sigma_px", o.max_distortion_sigma_px, 0.0, 1e6);
  r.optional("max_rms_px", o.max_rms_px, 0.0, 1e6);
  r.optional("failed_rms_px", o.failed_rms_px, 0.0, 1e6);
  r.optional("failed_focal_rel_sigma", o.failed_focal_rel_sigma, 0.0, 1e6);
  r.optional("coverage_columns", o.coverage_columns, 1, 1000);
}

DeterminedFocal determinedFocal(const IntrinsicsResult& r, int i) {
  const CalibCamera& c = r.camera;
  const size_t k = static_cast<size_t>(i);
  const bool valley = c.projection == ProjectionModel::kUnified || c.projection == ProjectionModel::kDoubleSphere;
  if (!valley) return {c.parameterName(i), c.params[k], r.has_sigma ? r.sigma[k] : 0.0};
  // g = f / s, s = 1 + xi: dg/df = 1 / s, dg/dxi = -f / s^2 (xi is parameter 8).
  const double s = 1 + c.projection_params[0];
  const double a = 1 / s, b = -c.params[k] / (s * s);
  const auto& C = r.covariance;
  const double var = a * a * C(i, i) + 2 * a * b * C(i, 8) + b * b * C(8, 8);
  return {c.parameterName(i) + " / (1 + xi)", c.params[k] / s, r.has_sigma ? std::sqrt(std::max(0.0, var)) : 0.0};
}

IntrinsicsCoverage measureCoverage(const IntrinsicsResult& r, int columns) {
  IntrinsicsCoverage c;
  const int w = r.camera.width, h = r.camera.height;
  c.cells_x = std::max(1, columns);
  c.cells_y = std::max(1, static_cast<int>(std::lround(static_cast<double>(c.cells_x) * h / std::max(1, w))));
  c.corners_per_cell.assign(static_cast<size_t>(c.cells_x * c.cells_y), 0);
  for (const CornerResidual& cr : r.residuals) {
    if (!cr.inlier || !cr.residual.allFinite()) continue;
    const int cx = std::clamp(static_cast<int>(cr.pixel.x() / w * c.cells_x), 0, c.cells_x - 1);
    const int cy = std::clamp(static_cast<int>(cr.pixel.y() / h * c.cells_y), 0, c.cells_y - 1);
    ++c.corners_per_cell[static_cast<size_t>(cy * c.cells_x + cx)];
  }
  const auto covered = std::count_if(c.corners_per_cell.begin(), c.corners_per_cell.end(),
                                     [](int n) { return n > 0; });
  c.image_share = static_cast<double>(covered) / c.corners_per_cell.size();

  // Board normal (target z) in the camera frame; it points back at the camera (z < 0).
  std::vector<Eigen::Vector3d> normals;
  for (const ViewStats& v : r.views) {
    Eigen::Vector3d n = v.T_C_T.linear().col(2);
    if (n.z() > 0) n = -n;
    normals.push_back(n);
    c.view_tilt_deg.push_back(std::acos(std::clamp(-n.z(), -1.0, 1.0)) * kDeg);
    // Rotation about the camera x axis shows as the normal's y, about y as its x.
    c.view_tilt_xy_deg.emplace_back(std::atan2(n.y(), -n.z()) * kDeg, std::atan2(-n.x(), -n.z()) * kDeg);
    c.max_tilt_deg = std::max(c.max_tilt_deg, c.view_tilt_deg.back());
  }
  double min_dot = 1;
  for (size_t i = 0; i < normals.size(); ++i)
    for (size_t j = i + 1; j < normals.size(); ++j) min_dot = std::min(min_dot, normals[i].dot(normals[j]));
  c.tilt_spread_deg = std::acos(std::clamp(min_dot, -1.0, 1.0)) * kDeg;
  return c;
}

double distortionFoldRadius(const CalibCamera& camera) {
  // Along the x axis (the tangential terms are small for any sane lens), the ray's angle theta
  // from 0 to 89.5 degrees: the image radius must keep growing (a ray outside the projection's
  // valid region ends it too).
  double best = 0;
  for (int k = 1; k <= 4000; ++k) {
    const double theta = 89.5 * M_PI / 180 * k / 4000.0;
    Eigen::Vector2d uv;
    if (!camera.project(Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)), uv)) return best;
    const double rd = std::hypot((uv.x() - camera.pu()) / camera.fu(), (uv.y() - camera.pv()) / camera.fv());
    if (!std::isfinite(rd)) return best;
    if (rd <= best) return best;  // stopped growing: folds here
    best = rd;
  }
  return std::numeric_limits<double>::infinity();
}

IntrinsicsJudgement judgeIntrinsics(const IntrinsicsResult& r, const IntrinsicsOptions& calib,
                                    const IntrinsicsVerdictOptions& o) {
  IntrinsicsJudgement j;
  CalibrationVerdict& v = j.verdict;
  const CalibCamera& c = r.camera;
  const int w = c.width, h = c.height;
  j.coverage = measureCoverage(r, o.coverage_columns);

  // ---- failed: the numbers cannot be a camera.
  for (const std::string& p : r.solver_problems)
    v.add(r.final_solve_usable ? Verdict::kWeak : Verdict::kFailed, "solver", p, kMoreViews);
  if (r.final_solve_usable && !r.final_solve_converged)
    v.add(Verdict::kWeak, "solver",
          strprintf("the last solve stopped at its iteration limit (%d) still improving: the cost is "
                    "flat along some parameter",
                    calib.max_iterations),
          kTilt);
  bool finite = true;
  for (int i = 0; i < kParameters; ++i) finite = finite && std::isfinite(c.parameter(i));
  if (!finite) v.add(Verdict::kFailed, "finite", "the intrinsics are not finite numbers", kMoreViews);
  if (!(std::isfinite(r.rms_px)) || r.corners_used == 0)
    v.add(Verdict::kFailed, "residuals", "no finite reprojection residual", kDetections);
  if (r.corners_not_projected > 0)
    v.add(Verdict::kFailed, "residuals",
          strprintf("%d corners lie behind the camera at the solution", r.corners_not_projected),
          kMoreViews);
  const double f_lo = calib.min_focal_over_width * w, f_hi = calib.max_focal_over_width * w;
  for (int i = 0; i < 2 && finite; ++i) {
    const double f = c.params[i];
    // The solve bounds the focal length; ending on a bound means the data pushed it out.
    if (f <= f_lo * 1.001 || f >= f_hi * 0.999)
      v.add(Verdict::kFailed, "plausibility",
            strprintf("%s = %.1f px is at the edge of the plausible range [%.0f, %.0f] px "
                      "(%.2g..%.2g x width): the views do not determine it",
                      c.parameterName(i).c_str(), f, f_lo, f_hi, calib.min_focal_over_width,
                      calib.max_focal_over_width),
            kTilt);
  }
  if (finite) {
    const bool inside = c.pu() > 0 && c.pu() < w - 1 && c.pv() > 0 && c.pv() < h - 1;
    if (!inside)
      v.add(Verdict::kFailed, "plausibility",
            strprintf("principal point (%.1f, %.1f) is not inside the %dx%d image", c.pu(), c.pv(), w, h),
            kFill);
  }
  for (int i = 0; i < 2 && finite && r.has_sigma; ++i) {
    const DeterminedFocal f = determinedFocal(r, i);
    if (f.sigma_px > o.failed_focal_rel_sigma * std::abs(f.px))
      v.add(Verdict::kFailed, "undetermined",
            strprintf("%s = %.1f px has a 1-sigma of %.3g px (%.0f %%): the views do not determine "
                      "the focal length at all",
                      f.name.c_str(), f.px, f.sigma_px, 100 * f.sigma_px / std::abs(f.px)),
            kTilt);
  }
  if (std::isfinite(r.rms_px) && r.rms_px > o.failed_rms_px)
    v.add(Verdict::kFailed, "residuals",
          strprintf("RMS reprojection error %.2f px > %.3g px", r.rms_px, o.failed_rms_px), kDetections);

  // Radii (distorted, normalised) the corners cover and the image corners need.
  double covered_rd = 0, image_rd = 0;
  Eigen::Vector2d farthest(c.pu(), c.pv());
  if (finite && c.fu() > 0 && c.fv() > 0) {
    for (const CornerResidual& cr : r.residuals) {
      if (!cr.inlier || !cr.residual.allFinite()) continue;
      const double rd = std::hypot((cr.pixel.x() - c.pu()) / c.fu(), (cr.pixel.y() - c.pv()) / c.fv());
      if (rd > covered_rd) covered_rd = rd, farthest = cr.pixel;
    }
    for (double u : {0.0, w - 1.0})
      for (double vv : {0.0, h - 1.0})
        image_rd = std::max(image_rd, std::hypot((u - c.pu()) / c.fu(), (vv - c.pv()) / c.fv()));
    const double fold = distortionFoldRadius(c);
    if (fold < covered_rd)
      v.add(Verdict::kFailed, "plausibility",
            "the distortion folds back inside the area the corners cover (the lens model is not "
            "one-to-one there)",
            kFill);
    else if (fold < image_rd)
      v.add(Verdict::kWeak, "distortion",
            strprintf("the distortion folds back at %.0f %% of the way to the image corners: "
                      "projections beyond it are wrong",
                      100 * fold / image_rd),
            kFill);
  }

  // ---- weak: the data do not pin the numbers down.
  const int views = static_cast<int>(r.views.size());
  if (views < o.min_views)
    v.add(Verdict::kWeak, "views", strprintf("%d views used < %d", views, o.min_views), kMoreViews);
  if (j.coverage.image_share < o.min_image_share)
    v.add(Verdict::kWeak, "coverage",
          strprintf("the corners cover %.0f %% of the image (%dx%d cells) < %.0f %%",
                    100 * j.coverage.image_share, j.coverage.cells_x, j.coverage.cells_y,
                    100 * o.min_image_share),
          kFill);
  if (j.coverage.tilt_spread_deg < o.min_tilt_spread_deg)
    v.add(Verdict::kWeak, "tilt",
          strprintf("the board normals span %.1f deg < %.0f deg (board tilt %.1f..%.1f deg)",
                    j.coverage.tilt_spread_deg, o.min_tilt_spread_deg,
                    j.coverage.view_tilt_deg.empty() ? 0.0
                        : *std::min_element(j.coverage.view_tilt_deg.begin(), j.coverage.view_tilt_deg.end()),
                    j.coverage.max_tilt_deg),
          kTilt);

  std::vector<std::string> poor;
  if (finite) {
    // Each parameter's 1-sigma and its shift without the outlier rejection, as pixels at the
    // farthest corner the views cover.
    Eigen::Vector3d ray;
    const bool have_ray = c.unproject(farthest, ray);
    const CalibCamera& all = r.camera_all_corners;
    for (int i = 0; i < kParameters; ++i) {
      if (!c.hasParameter(i)) continue;
      if (r.has_sigma && have_ray) {
        CalibCamera moved = c;
        moved.parameter(i) += r.sigma[i];
        Eigen::Vector2d uv;
        j.sigma_effect_px[i] = moved.project(ray, uv) ? (uv - farthest).norm()
                                                      : std::numeric_limits<double>::infinity();
      }
      j.rejection_shift[i] = all.width > 0 ? c.parameter(i) - all.parameter(i) : 0;
    }
    // Poorly determined by the covariance (formal 1-sigma, poses marginalised).
    for (int i = 0; i < 4 && r.has_sigma; ++i) {
      const DeterminedFocal f = i < 2 ? determinedFocal(r, i) : DeterminedFocal{c.parameterName(i), c.params[i], r.sigma[i]};
      const double scale = i < 2 ? std::abs(f.px) : static_cast<double>(w);
      const double limit = i < 2 ? o.max_focal_rel_sigma : o.max_principal_point_rel_sigma;
      if (!(f.sigma_px / scale > limit)) continue;
      j.poorly_determined[static_cast<size_t>(i)] = true;
      poor.push_back(strprintf("%s (1-sigma %.3g px = %.2f %% of %s > %.2f %%)", f.name.c_str(),
                               f.sigma_px, 100 * f.sigma_px / scale, i < 2 ? "its value" : "the width",
                               100 * limit));
    }
    // The lens parameters: distortion coefficients and projection parameters (indices 4..9).
    std::vector<int> lens;
    for (int i = 4; i < kParameters; ++i)
      if (c.hasParameter(i)) lens.push_back(i);
    if (r.has_sigma && have_ray && !lens.empty()) {
      // Jacobian of the projection of the farthest ray w.r.t. the lens parameters (central
      // differences), then the 2x2 covariance of the pixel: largest axis. Omni's and ds' xi
      // trades against the focal length along a valley (determinedFocal): there the focal
      // lengths join the lens parameters, or the valley would show as an undetermined lens.
      std::vector<int> joint = lens;
      if (c.projection == ProjectionModel::kUnified || c.projection == ProjectionModel::kDoubleSphere)
        joint.insert(joint.begin(), {0, 1});
      const int m = static_cast<int>(joint.size());
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2, m), C(m, m);
      bool ok = true;
      for (int k = 0; k < m && ok; ++k) {
        const int i = joint[static_cast<size_t>(k)];
        const double step = 1e-6 * std::max(1.0, std::abs(c.parameter(i)));
        CalibCamera plus = c, minus = c;
        plus.parameter(i) += step;
        minus.parameter(i) -= step;
        Eigen::Vector2d up, um;
        ok = plus.project(ray, up) && minus.project(ray, um);
        J.col(k) = (up - um) / (2 * step);
        for (int l = 0; l < m; ++l) C(k, l) = r.covariance(i, joint[static_cast<size_t>(l)]);
      }
      const Eigen::Matrix2d P = J * C * J.transpose();
      j.distortion_sigma_px = ok ? std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(P).eigenvalues().maxCoeff()))
                                 : std::numeric_limits<double>::infinity();
      if (j.distortion_sigma_px > o.max_distortion_sigma_px) {
        std::string names;
        for (int i : lens) {
          if (c.model == DistortionModel::kRadialTangential && i < 8 && r.sigma[i] == 0) continue;
          j.poorly_determined[static_cast<size_t>(i)] = true;
          names += (names.empty() ? "" : ", ") + c.parameterName(i);
        }
        poor.push_back(strprintf("%s (together, 1-sigma moves the farthest covered corner by %.2f px > "
                                 "%.2f px)",
                                 names.c_str(), j.distortion_sigma_px, o.max_distortion_sigma_px));
      }
    }
    // Poorly determined by the geometry of the views, whatever the covariance says (it assumes the
    // model is right and the corners independent; on real data it is several times too small):
    // boards seen at one angle leave the focal length to the distortion and the distance
    // (Sturm and Maybank's degenerate configurations), corners in part of the image leave the
    // distortion and the principal point to extrapolation.
    if (j.coverage.tilt_spread_deg < o.min_tilt_spread_deg)
      for (int i = 0; i < 2; ++i)
        if (!j.poorly_determined[static_cast<size_t>(i)]) {
          j.poorly_determined[static_cast<size_t>(i)] = true;
          poor.push_back(c.parameterName(i) + " (the board was seen at one angle)");
        }
    if (j.coverage.image_share < o.min_image_share) {
      std::string names;
      for (int i = 2; i < kParameters; ++i) {
        if (j.poorly_determined[static_cast<size_t>(i)] || !c.hasParameter(i)) continue;
        if (c.model == DistortionModel::kRadialTangential && i >= 6 && i < 8 && c.params[i] == 0) continue;
        j.poorly_determined[static_cast<size_t>(i)] = true;
        names += (names.empty() ? "" : ", ") + c.parameterName(i);
      }
      if (!names.empty())
        poor.push_back(names + " (extrapolated over the part of the image no corner reached)");
    }
    if (!r.has_sigma && calib.compute_covariance)
      v.add(Verdict::kWeak, "covariance", "the covariance could not be computed (singular)", kMoreViews);
  }
  if (!poor.empty()) {
    std::string list;
    for (const auto& p : poor) list += (list.empty() ? "" : "; ") + p;
    v.add(Verdict::kWeak, "poorly determined", list,
          j.coverage.tilt_spread_deg < o.min_tilt_spread_deg ? kTilt : kMoreViews);
  }
  if (std::isfinite(r.rms_px) && r.rms_px > o.max_rms_px && r.rms_px <= o.failed_rms_px)
    v.add(Verdict::kWeak, "residuals",
          strprintf("RMS reprojection error %.2f px > %.3g px", r.rms_px, o.max_rms_px), kDetections);
  return j;
}

}  // namespace adugs::calib

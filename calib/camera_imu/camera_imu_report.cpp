#include "calib/camera_imu/camera_imu_report.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "calib/kalibr_yaml.h"
#include "calib/text_format.h"

namespace adugs::calib {
namespace {

std::string matrixYaml(const Eigen::Matrix4d& m, const std::string& indent) {
  std::string s;
  for (int r = 0; r < 4; ++r) {
    s += indent + "- [";
    for (int c = 0; c < 4; ++c) s += (c ? ", " : "") + formatDouble(m(r, c));
    s += "]\n";
  }
  return s;
}

std::string matrixText(const Eigen::Matrix4d& m) {
  std::string s;
  for (int r = 0; r < 4; ++r)
    s += strprintf("  [% .8f % .8f % .8f % .8f]\n", m(r, 0), m(r, 1), m(r, 2), m(r, 3));
  return s;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

Eigen::Vector3d axisRms(const std::vector<TimedVector>& v) {
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  for (const auto& x : v) sq += x.v.cwiseAbs2();
  return v.empty() ? sq : (sq / v.size()).cwiseSqrt();
}

void text(cv::Mat& img, const std::string& t, int x, int y, double scale = 0.45) {
  cv::putText(img, t, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
}

}  // namespace

std::string formatCamchainImuCamYaml(const CalibCamera& camera, const CameraImuResult& r,
                                     const std::string& name, const std::string& rostopic) {
  std::string s = formatCamchainYaml(camera, name, rostopic);
  s += "  T_cam_imu:\n" + matrixYaml(r.T_C_I.matrix(), "  ");
  s += "  timeshift_cam_imu: " + formatDouble(r.time_shift_s) + "\n";
  return s;
}

void compareTransforms(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double& angle_deg,
                       double& distance_m) {
  const Eigen::AngleAxisd d(a.linear().transpose() * b.linear());
  angle_deg = std::abs(d.angle()) * 180.0 / M_PI;
  distance_m = (a.translation() - b.translation()).norm();
}

std::string formatCameraImuReport(const CameraImuResult& r, const CameraImuOptions& o,
                                  const CalibrationVerdict& verdict,
                                  const CameraImuReportContext& ctx) {
  std::string s = "Camera-IMU calibration (adugs calib camera-imu)\n\n";
  s += "Inputs\n";
  s += "  corners:     " + ctx.corners_input + "\n";
  s += "  imu:         " + ctx.imu_input + "\n";
  s += "  intrinsics:  " + ctx.intrinsics_input + "\n";
  s += strprintf(
      "  frames: %d used of %d views (>= %d corners, every %d), %d corners, "
      "PnP RMS %.3f px\n",
      r.frames_used, r.views_given, o.min_corners, o.frame_step, r.corners_in_frames, r.pnp_rms_px);
  s += strprintf(
      "  IMU samples: %d; rotation excitation (RMS rate per principal axis): "
      "%.3f %.3f %.3f rad/s\n",
      r.imu_samples_used, r.excitation(0), r.excitation(1), r.excitation(2));
  s += strprintf("  frames with the board span %.1f s", r.duration_s);
  if (r.frames_outside_imu > 0)
    s += strprintf("; %d of %d frames with the target lie outside the IMU's time span (dropped)",
                   r.frames_outside_imu, r.frames_with_target);
  s += "\n";
  s += strprintf("  spline: %d control points at %.4g Hz; %d solver iterations; %.2f s\n\n",
                 r.control_points, o.knot_rate_hz, r.iterations, r.seconds);
  s += formatVerdict(verdict, "camchain-imucam.yaml") + "\n";
  if (!r.solved) return s + "Not solved: there is no rotation to align the camera with the gyro.\n";

  s += "Result\n";
  s +=
      "T_cam_imu (Kalibr; maps IMU points into the camera frame):\n" + matrixText(r.T_C_I.matrix());
  s += "T_imu_cam (EuRoC T_BS; camera -> IMU):\n" + matrixText(r.T_C_I.inverse().matrix());
  s += strprintf("timeshift_cam_imu: %.6f s  (t_imu = t_cam + shift)%s\n", r.time_shift_s,
                 o.estimate_time_offset ? "" : "  [fixed]");
  s += strprintf("gravity (target frame): [%.5f, %.5f, %.5f] m/s^2\n", r.gravity_T(0),
                 r.gravity_T(1), r.gravity_T(2));
  s += strprintf("gyro bias:  [% .6f, % .6f, % .6f] rad/s\n", r.gyro_bias(0), r.gyro_bias(1),
                 r.gyro_bias(2));
  s += strprintf("accel bias: [% .5f, % .5f, % .5f] m/s^2\n", r.accel_bias(0), r.accel_bias(1),
                 r.accel_bias(2));
  if (r.has_sigma)
    s += strprintf("1-sigma (covariance of the final problem, %.1f s): rotation [%.3f, %.3f, %.3f] "
                   "deg, camera position in the IMU frame [%.2f, %.2f, %.2f] mm, time shift %.3f ms\n",
                   r.covariance_seconds, r.sigma_rotation(0) * 180 / M_PI,
                   r.sigma_rotation(1) * 180 / M_PI, r.sigma_rotation(2) * 180 / M_PI,
                   r.sigma_translation(0) * 1000, r.sigma_translation(1) * 1000,
                   r.sigma_translation(2) * 1000, r.sigma_time_shift_s * 1000);
  s += "\n";

  s += "Initial guess\n";
  Eigen::Isometry3d init = Eigen::Isometry3d::Identity();
  init.linear() = r.R_C_I_init;
  double a = 0, d = 0;
  compareTransforms(init, r.T_C_I, a, d);
  s += strprintf(
      "  time shift from rate correlation: %.4f s; R_C_I from Kabsch (rate residual "
      "RMS %.4f rad/s), %.3f deg from the final rotation\n\n",
      r.time_shift_init_s, r.init_rate_rms, a);

  s += "Residuals\n";
  s += strprintf(
      "  reprojection over the %d corners that project: RMS %.3f px, median %.3f, 90%% %.3f, "
      "99%% %.3f, max %.3f px; %d corners above the Huber threshold %.2f px\n",
      r.corners_used, r.reprojection_rms_px, percentile(r.corner_errors_px, 0.5),
      percentile(r.corner_errors_px, 0.9), percentile(r.corner_errors_px, 0.99),
      percentile(r.corner_errors_px, 1.0), r.corners_downweighted, o.huber_px);
  if (r.corners_behind_camera > 0)
    s += strprintf("  %d corners lie BEHIND the camera at this solution (no reprojection error)\n",
                   r.corners_behind_camera);
  const Eigen::Vector3d g = axisRms(r.gyro_residuals), ac = axisRms(r.accel_residuals);
  s +=
      strprintf("  gyro:  RMS %.5f rad/s (x %.5f, y %.5f, z %.5f)\n", r.gyro_rms, g(0), g(1), g(2));
  s += strprintf("  accel: RMS %.4f m/s^2 (x %.4f, y %.4f, z %.4f)\n", r.accel_rms, ac(0), ac(1),
                 ac(2));

  if (ctx.has_reference) {
    const Eigen::Isometry3d ref_C_I = ctx.reference_T_I_C.inverse();
    compareTransforms(ref_C_I, r.T_C_I, a, d);
    // Translation compared as the camera position in the IMU frame (what T_BS states).
    const double dp = (ctx.reference_T_I_C.translation() - r.T_C_I.inverse().translation()).norm();
    s += "\nComparison with " + ctx.reference_name + " (T_BS)\n";
    s += strprintf("  rotation difference:    %.4f deg\n", a);
    s += strprintf("  translation difference: %.2f mm (camera position in the IMU frame)\n",
                   dp * 1000);
  }
  return s;
}

cv::Mat renderImuResidualPlot(const std::vector<TimedVector>& res, const std::string& title,
                              const std::string& unit, double sigma) {
  const int W = 1200, panel = 180, top = 40, left = 80, right = 20;
  const int H = top + 3 * panel + 40;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  text(img, title, left, 25, 0.6);
  if (res.empty()) return img;
  const double t0 = res.front().t, t1 = std::max(res.back().t, t0 + 1e-9);
  double lim = 4 * sigma;
  for (const auto& r : res) lim = std::max(lim, std::min(r.v.cwiseAbs().maxCoeff(), 10 * sigma));
  const char* axes[3] = {"x", "y", "z"};
  const cv::Scalar colours[3] = {cv::Scalar(40, 40, 220), cv::Scalar(40, 160, 40),
                                 cv::Scalar(200, 80, 30)};
  for (int a = 0; a < 3; ++a) {
    const int y0 = top + a * panel, y1 = y0 + panel - 20, ym = (y0 + y1) / 2;
    cv::rectangle(img, cv::Rect(left, y0, W - left - right, y1 - y0), cv::Scalar(0, 0, 0), 1);
    auto yOf = [&](double v) {
      return static_cast<int>(ym - std::clamp(v, -lim, lim) / lim * (y1 - y0) / 2);
    };
    for (double k : {-3.0, 3.0})
      cv::line(img, {left, yOf(k * sigma)}, {W - right, yOf(k * sigma)}, cv::Scalar(160, 160, 160),
               1);
    cv::Point prev(-1, -1);
    for (const auto& r : res) {
      const cv::Point pt(left + static_cast<int>((r.t - t0) / (t1 - t0) * (W - left - right)),
                         yOf(r.v(a)));
      if (prev.x >= 0) cv::line(img, prev, pt, colours[a], 1);
      prev = pt;
    }
    text(img, std::string(axes[a]) + " [" + unit + "]", 5, ym);
    text(img, strprintf("%.3g", lim), 5, y0 + 12, 0.4);
    text(img, strprintf("%.3g", -lim), 5, y1, 0.4);
  }
  text(img,
       strprintf("time [s]  %.1f .. %.1f   (grey: +-3 sigma = %.3g %s)", t0, t1, 3 * sigma,
                 unit.c_str()),
       left, H - 12);
  return img;
}

cv::Mat renderReprojectionHistogram(const std::vector<double>& errors) {
  const int W = 800, H = 450, left = 60, bottom = 50, top = 40, right = 20;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  text(img, "Corner reprojection error histogram", left, 25, 0.6);
  if (errors.empty()) return img;
  const double hi = std::max(0.5, percentile(errors, 0.995));
  const int bins = 50;
  std::vector<int> count(bins, 0);
  for (double e : errors) ++count[std::min(bins - 1, static_cast<int>(e / hi * bins))];
  const int peak = *std::max_element(count.begin(), count.end());
  const double bw = static_cast<double>(W - left - right) / bins;
  for (int b = 0; b < bins; ++b) {
    const int h = static_cast<int>(static_cast<double>(count[b]) / peak * (H - top - bottom));
    cv::rectangle(img, cv::Point(static_cast<int>(left + b * bw), H - bottom - h),
                  cv::Point(static_cast<int>(left + (b + 1) * bw) - 1, H - bottom),
                  cv::Scalar(200, 120, 40), cv::FILLED);
  }
  cv::rectangle(img, cv::Rect(left, top, W - left - right, H - top - bottom), cv::Scalar(0, 0, 0),
                1);
  text(img, "0", left, H - bottom + 18);
  text(img, strprintf("%.2f px", hi), W - right - 60, H - bottom + 18);
  text(img,
       strprintf("%zu corners, median %.3f px, 90%% %.3f px (last bin includes larger)",
                 errors.size(), percentile(errors, 0.5), percentile(errors, 0.9)),
       left, H - 12);
  text(img, std::to_string(peak), 5, top + 12);
  return img;
}

}  // namespace adugs::calib

#include "app/run_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "data/formats/atomic_file.h"
#include "data/formats/trajectory_io.h"
#include "vio/eval/consistency.h"
#include "vio/eval/trajectory_eval.h"
#include "vio/eval/trajectory_plot.h"

namespace adugs::app {
namespace fs = std::filesystem;

// Seconds after the first pose from which ate_se3_rmse_settled_m counts.
constexpr double kSettleS = 3.0;

void writeRunOutputs(const std::string& out_dir, const std::string& estimator,
                     const std::string& trajectory_path, const std::string& gt_path,
                     const RunStats& stats) {
  std::ostringstream summary;
  summary.precision(6);
  summary << "estimator: " << estimator << "\n"
          << "frames: " << stats.frames << "\n"
          << "skipped_frames: " << stats.skipped_frames << "\n"
          << "imu_samples: " << stats.imu_samples << "\n"
          << "poses: " << stats.poses << "\n"
          << "sequence_s: " << stats.sequence_s << "\n"
          << "wall_s: " << stats.wall_s << "\n"
          << "realtime_factor: " << (stats.wall_s > 0 ? stats.sequence_s / stats.wall_s : 0.0)
          << "\n"
          << stats.extra_summary;

  std::cout << "adugs " << stats.command << " (" << estimator << "): " << stats.poses << " poses from " << stats.frames
            << " frames (" << stats.sequence_s << " s of data) in " << stats.wall_s << " s\n";
  if (!trajectory_path.empty()) std::cout << "  trajectory  " << trajectory_path << "\n";

  if (!gt_path.empty() && stats.poses >= 3) {
    const auto est = data::readTrajectory(trajectory_path);
    data::TrajectoryReadInfo gt_info;
    const auto gt = data::readTrajectory(gt_path, &gt_info);
    if (gt_info.duplicates_dropped > 0)
      std::cout << "  warning     " << gt_path << ": " << gt_info.duplicates_dropped
                << " ground-truth poses with a repeated timestamp dropped (first at line "
                << gt_info.first_duplicate_line << ")\n";
    vio::EvalOptions options;
    options.align = vio::AlignMode::kSe3;
    const vio::EvalResult r = vio::evaluateTrajectory(est, gt, options);
    const vio::CorrectRateResult& cr = r.correct_rate;
    summary << "ate_se3_rmse_m: " << r.ate.translation.rmse << "\n"
            << "ate_se3_max_m: " << r.ate.translation.max << "\n"
            << "ate_poses: " << r.ate.translation.count << "\n"
            << "gt_length_m: " << r.gt_length_m << "\n"
            << "correct_rate: " << cr.correct_rate << "\n"
            << "correct_time_s: " << cr.correct_time_s << "\n"
            << "correct_rate_thresholds: {max_position_m: " << options.correct_rate.max_position_m
            << ", max_angle_deg: " << options.correct_rate.max_angle_deg << "}\n"
            << "gt_duplicates_dropped: " << gt_info.duplicates_dropped << "\n";
    // The odometry once settled: after a moving start the window spends seconds correcting the
    // initialisation's scale and velocity (simulator street: 0.12 m in the first 3 s against
    // 0.03 m after), which can be most of a short run's ATE and moves with anything that changes
    // which window initialises (doc/results.md, "The initialisation's transient").
    vio::EvalOptions settled_options = options;
    settled_options.skip_first_s = kSettleS;
    try {
      const vio::EvalResult settled = vio::evaluateTrajectory(est, gt, settled_options);
      summary << "ate_se3_rmse_settled_m: " << settled.ate.translation.rmse << "  # the poses from " << kSettleS
              << " s after the first on, aligned on their own (adugs eval --skip-first " << kSettleS << ")\n";
    } catch (const std::invalid_argument& e) {
      summary << "ate_se3_rmse_settled_m: -1  # not evaluated: " << e.what() << "\n";
    }
    // The scale apart from the shape: on a gentle drive the accelerometer barely observes the
    // scale, and a 1 % error over 30 m straight is most of the se3 ATE, whatever else the run did
    // (simulator street: scale errors of +-0.5-2 %; doc/results.md, "The street's ATE is its scale").
    vio::EvalOptions sim3_options = options;
    sim3_options.align = vio::AlignMode::kSim3;
    std::optional<vio::EvalResult> shape;
    try {
      shape = vio::evaluateTrajectory(est, gt, sim3_options);
      summary << "ate_sim3_rmse_m: " << shape->ate.translation.rmse
              << "  # aligned with a scale (adugs eval --align sim3): the trajectory's shape\n"
              << "scale_error_percent: " << shape->T_G_E.lengthErrorPercent()
              << "  # how much longer the estimate is than the ground truth (-1: 1 % short)\n";
    } catch (const std::invalid_argument& e) {
      summary << "ate_sim3_rmse_m: -1  # not evaluated: " << e.what() << "\n";
    }
    if (stats.relative_poses && !stats.relative_poses->empty()) {
      const vio::ConsistencyResult c = vio::evaluateConsistency(*stats.relative_poses, gt);
      summary << "nees_relative: {pose: " << c.nees_pose << ", position: " << c.nees_position
              << ", yaw: " << c.nees_yaw << ", within_95: " << c.within_95 << ", count: " << c.count
              << "}  # newest window frame against the oldest; consistent: 6, 3, 1, 0.95\n";
      std::printf("  NEES        pose %.2f (6), position %.2f (3), yaw %.2f (1) over %zu windows\n", c.nees_pose,
                  c.nees_position, c.nees_yaw, c.count);
    }
    const std::string plot = (fs::path(out_dir) / "eval.png").string();
    vio::PlotOptions plot_options;
    plot_options.title = "adugs " + stats.command + " (" + estimator + ")";
    vio::writeEvalPlot(plot, r, plot_options);
    char line[256];
    std::snprintf(line, sizeof(line),
                  "  ATE (se3)   RMSE %.4f m, max %.4f m over %zu poses, %.2f m travelled\n",
                  r.ate.translation.rmse, r.ate.translation.max, r.ate.translation.count,
                  r.gt_length_m);
    std::cout << line;
    if (shape) {
      const double length_error = shape->T_G_E.lengthErrorPercent();
      std::snprintf(line, sizeof(line), "  ATE (sim3)  RMSE %.4f m, with the scale aligned: the estimate is %.2f %% %s\n",
                    shape->ate.translation.rmse, std::abs(length_error), length_error < 0 ? "short" : "long");
      std::cout << line;
    }
    std::snprintf(line, sizeof(line),
                  "  CR          %.4f (correct %.2f s of %.2f s; <= %g m, <= %g deg, OpenLORIS)\n",
                  cr.correct_rate, cr.correct_time_s, cr.span_s,
                  options.correct_rate.max_position_m, options.correct_rate.max_angle_deg);
    std::cout << line << "  plot        " << plot << "\n";
  }
  const std::string summary_path = (fs::path(out_dir) / "summary.yaml").string();
  data::writeTextFileAtomically(summary_path, summary.str());
  std::cout << "  summary     " << summary_path << "\n";
}

}  // namespace adugs::app

// `adugs eval`: ATE, RPE and OpenLORIS' correct rate of an estimated trajectory against ground
// truth (TUM or EuRoC CSV), printed as a table, optionally saved as JSON and as a plot.
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "data/formats/atomic_file.h"
#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "vio/eval/trajectory_eval.h"
#include "vio/eval/trajectory_plot.h"

namespace adugs::app {
namespace {

struct EvalArgs {
  std::string est_path;
  std::string gt_path;
  std::string align = "se3";
  int align_frames = -1;
  double skip_first_s = 0;
  double max_dt_s = 0.01;
  std::vector<double> rpe_lengths_m;
  double cr_max_position_m = 1.0;
  double cr_max_angle_deg = 30.0;
  std::string plot_path;
  std::string json_path;
};

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  va_list args, again;
  va_start(args, fmt);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, args);
  va_end(args);
  std::string out(n > 0 ? static_cast<size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, fmt, again);
  va_end(again);
  return out;
}

std::string statsRow(const char* name, const vio::ErrorStats& s) {
  return format("  %-10s %11.6f %11.6f %11.6f %11.6f %11.6f %11.6f %7zu\n", name, s.rmse, s.mean,
                s.median, s.std, s.min, s.max, s.count);
}

double rotationAngleDeg(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle() * 180.0 / EIGEN_PI;
}

// " (N duplicate stamps dropped)" or nothing.
std::string duplicatesNote(const data::TrajectoryReadInfo& info) {
  if (info.duplicates_dropped == 0) return "";
  return format(", %zu duplicate stamp%s dropped", info.duplicates_dropped,
                info.duplicates_dropped == 1 ? "" : "s");
}

std::string report(const EvalArgs& a, const data::TrajectoryReadInfo& est_info,
                   const data::TrajectoryReadInfo& gt_info, const vio::EvalResult& r) {
  std::string out = "adugs eval\n";
  out += format("  estimate      %s  (%s, %zu poses%s)\n", a.est_path.c_str(),
                data::trajectoryFormatName(est_info.format), r.est_poses,
                duplicatesNote(est_info).c_str());
  out += format("  ground truth  %s  (%s, %zu poses%s)\n", a.gt_path.c_str(),
                data::trajectoryFormatName(gt_info.format), r.gt_poses,
                duplicatesNote(gt_info).c_str());
  if (a.skip_first_s > 0)
    out += format("  skipped       the estimate's first %g s (--skip-first): %zu of its poses evaluated\n",
                  a.skip_first_s, r.est_matched.size());
  out += format("  matched       %zu pairs within %g s\n", r.pairs.size(), a.max_dt_s);
  const Eigen::Vector3d& t = r.T_G_E.t_G_E;
  if (r.align_mode == vio::AlignMode::kNone) {
    out += "  alignment     none\n";
  } else {
    out += format(
        "  alignment     %s on %s%zu pairs: rotation %.4f deg, translation [%.4f, %.4f, %.4f] m, "
        "scale %.6f\n",
        vio::alignModeName(r.align_mode),
        r.align_pairs_used == r.pairs.size() ? "all " : "the first ", r.align_pairs_used,
        rotationAngleDeg(r.T_G_E.R_G_E), t.x(), t.y(), t.z(), r.T_G_E.scale);
    if (r.align_mode == vio::AlignMode::kSim3)
      out += format("  scale error   the estimate is %.3f %% %s\n", std::abs(r.T_G_E.lengthErrorPercent()),
                    r.T_G_E.lengthErrorPercent() < 0 ? "short" : "long");
  }
  out += format("  gt length     %.3f m over %.2f s\n\n", r.gt_length_m,
                data::nsToSec(r.gt_matched.back().t_ns - r.gt_matched.front().t_ns));

  out += "ATE (absolute trajectory error, after alignment)\n";
  out += format("  %-10s %11s %11s %11s %11s %11s %11s %7s\n", "", "rmse", "mean", "median", "std",
                "min", "max", "count");
  out += statsRow("trans [m]", r.ate.translation);
  out += statsRow("rot [deg]", r.ate.rotation);

  const vio::CorrectRateResult& cr = r.correct_rate;
  out +=
      format("\nCorrect rate (OpenLORIS: position error <= %g m and orientation error <= %g deg)\n",
             a.cr_max_position_m, a.cr_max_angle_deg);
  out += format("  CR %.4f: correct %.3f s of %.3f s, %zu of %zu matched poses correct\n",
                cr.correct_rate, cr.correct_time_s, cr.span_s, cr.correct_poses, cr.poses);

  out += "\nRPE (relative pose error over ground-truth travelled distance)\n";
  if (r.rpe.empty()) {
    out += "  (none: the ground truth does not move)\n";
    return out;
  }
  out += format("  %9s %7s %11s %11s %11s %10s %10s %10s %10s %10s\n", "length[m]", "count",
                "trans", "trans", "trans", "trans", "trans", "rot", "rot", "yaw");
  out += format("  %9s %7s %11s %11s %11s %10s %10s %10s %10s %10s\n", "", "", "rmse[m]", "mean[m]",
                "median[m]", "mean[%]", "median[%]", "mean[deg]", "med.[deg]", "mean[deg]");
  for (const vio::RpeResult& s : r.rpe) {
    if (s.translation_m.count == 0) {
      out += format("  %9.3f %7d   (no segment of this length)\n", s.length_m, 0);
      continue;
    }
    out += format("  %9.3f %7zu %11.6f %11.6f %11.6f %10.4f %10.4f %10.4f %10.4f %10.4f\n",
                  s.length_m, s.translation_m.count, s.translation_m.rmse, s.translation_m.mean,
                  s.translation_m.median, s.translation_pct.mean, s.translation_pct.median,
                  s.rotation_deg.mean, s.rotation_deg.median, s.yaw_deg.mean);
  }
  return out;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += format("\\u%04x", c);
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string jsonNumber(double v) { return std::isfinite(v) ? format("%.17g", v) : "null"; }

std::string jsonStats(const vio::ErrorStats& s) {
  return "{\"rmse\": " + jsonNumber(s.rmse) + ", \"mean\": " + jsonNumber(s.mean) +
         ", \"median\": " + jsonNumber(s.median) + ", \"std\": " + jsonNumber(s.std) +
         ", \"min\": " + jsonNumber(s.min) + ", \"max\": " + jsonNumber(s.max) +
         ", \"count\": " + std::to_string(s.count) + "}";
}

std::string json(const EvalArgs& a, const data::TrajectoryReadInfo& est_info,
                 const data::TrajectoryReadInfo& gt_info, const vio::EvalResult& r) {
  std::ostringstream o;
  const Eigen::Matrix3d& R = r.T_G_E.R_G_E;
  const Eigen::Vector3d& t = r.T_G_E.t_G_E;
  const vio::CorrectRateResult& cr = r.correct_rate;
  o << "{\n  \"estimate\": {\"path\": " << jsonString(a.est_path) << ", \"poses\": " << r.est_poses
    << ", \"duplicates_dropped\": " << est_info.duplicates_dropped << "},\n"
    << "  \"ground_truth\": {\"path\": " << jsonString(a.gt_path) << ", \"poses\": " << r.gt_poses
    << ", \"duplicates_dropped\": " << gt_info.duplicates_dropped << "},\n"
    << "  \"skip_first_s\": " << jsonNumber(a.skip_first_s) << ",\n"
    << "  \"max_dt_s\": " << jsonNumber(a.max_dt_s) << ",\n  \"matched_pairs\": " << r.pairs.size()
    << ",\n"
    << "  \"alignment\": {\"mode\": \"" << vio::alignModeName(r.align_mode)
    << "\", \"pairs_used\": " << r.align_pairs_used << ", \"scale\": " << jsonNumber(r.T_G_E.scale)
    << ",\n    \"R_G_E\": [";
  for (int i = 0; i < 3; ++i)
    o << (i ? ", " : "") << "[" << jsonNumber(R(i, 0)) << ", " << jsonNumber(R(i, 1)) << ", "
      << jsonNumber(R(i, 2)) << "]";
  o << "],\n    \"t_G_E\": [" << jsonNumber(t.x()) << ", " << jsonNumber(t.y()) << ", "
    << jsonNumber(t.z()) << "]},\n  \"gt_length_m\": " << jsonNumber(r.gt_length_m) << ",\n"
    << "  \"ate\": {\"translation_m\": " << jsonStats(r.ate.translation)
    << ",\n          \"rotation_deg\": " << jsonStats(r.ate.rotation) << "},\n"
    << "  \"correct_rate\": {\"cr\": " << jsonNumber(cr.correct_rate)
    << ", \"correct_time_s\": " << jsonNumber(cr.correct_time_s)
    << ", \"span_s\": " << jsonNumber(cr.span_s) << ", \"correct_poses\": " << cr.correct_poses
    << ", \"poses\": " << cr.poses
    << ",\n                   \"max_position_m\": " << jsonNumber(a.cr_max_position_m)
    << ", \"max_angle_deg\": " << jsonNumber(a.cr_max_angle_deg) << "},\n  \"rpe\": [";
  for (size_t i = 0; i < r.rpe.size(); ++i) {
    const vio::RpeResult& s = r.rpe[i];
    o << (i ? "," : "") << "\n    {\"length_m\": " << jsonNumber(s.length_m)
      << ",\n     \"translation_m\": " << jsonStats(s.translation_m)
      << ",\n     \"translation_pct\": " << jsonStats(s.translation_pct)
      << ",\n     \"rotation_deg\": " << jsonStats(s.rotation_deg)
      << ",\n     \"yaw_deg\": " << jsonStats(s.yaw_deg) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

// Warns on stderr about the poses the reader dropped for a repeated timestamp.
void warnDuplicates(const std::string& path, const data::TrajectoryReadInfo& info) {
  if (info.duplicates_dropped == 0) return;
  std::cerr << "warning: " << path << ": " << info.duplicates_dropped << " pose"
            << (info.duplicates_dropped == 1 ? "" : "s")
            << " with the timestamp of the previous pose dropped (first at line "
            << info.first_duplicate_line << "); the first pose of each timestamp is used\n";
}

void runEval(const EvalArgs& a) {
  data::TrajectoryReadInfo est_info, gt_info;
  const data::Trajectory est = data::readTrajectory(a.est_path, &est_info);
  const data::Trajectory gt = data::readTrajectory(a.gt_path, &gt_info);
  warnDuplicates(a.est_path, est_info);
  warnDuplicates(a.gt_path, gt_info);

  vio::EvalOptions options;
  options.align = vio::parseAlignMode(a.align);  // already checked by CLI11
  options.align_frames = a.align_frames;
  options.skip_first_s = a.skip_first_s;
  options.max_dt_ns = data::secToNs(a.max_dt_s);
  options.rpe_lengths_m = a.rpe_lengths_m;
  options.correct_rate.max_position_m = a.cr_max_position_m;
  options.correct_rate.max_angle_deg = a.cr_max_angle_deg;
  vio::EvalResult result;
  try {
    result = vio::evaluateTrajectory(est, gt, options);
  } catch (const std::invalid_argument& e) {
    throw data::InputError(a.est_path, 0, "",
                           std::string(e.what()) + " [ground truth: " + a.gt_path + "]");
  }

  std::cout << report(a, est_info, gt_info, result) << std::flush;
  if (!a.json_path.empty()) {
    data::writeTextFileAtomically(a.json_path, json(a, est_info, gt_info, result));
    std::cout << "\nwrote " << a.json_path << "\n";
  }
  if (!a.plot_path.empty()) {
    vio::PlotOptions plot;
    plot.title = "adugs eval: " + std::filesystem::path(a.est_path).filename().string() + " vs " +
                 std::filesystem::path(a.gt_path).filename().string();
    vio::writeEvalPlot(a.plot_path, result, plot);
    std::cout << (a.json_path.empty() ? "\n" : "") << "wrote " << a.plot_path << "\n";
  }
}

}  // namespace

void registerEvalCommand(CLI::App& root) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = root.add_subcommand(
      "eval",
      "Trajectory error (ATE, RPE, OpenLORIS correct rate) of an estimate against ground truth, "
      "TUM or EuRoC CSV files");
  cmd->add_option("--est", args->est_path,
                  "estimated trajectory (TUM: t tx ty tz qx qy qz qw, seconds)")
      ->required();
  cmd->add_option("--gt", args->gt_path, "ground truth (EuRoC CSV with ns and qw first, or TUM)")
      ->required();
  cmd->add_option("--align", args->align, "alignment before measuring errors")
      ->check(CLI::IsMember({"se3", "sim3", "posyaw", "none"}))
      ->capture_default_str();
  cmd->add_option("--align-frames", args->align_frames,
                  "align on the first N matched poses only (default: all)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--skip-first", args->skip_first_s,
                  "leave out the estimate's poses within this many seconds of its first one (the "
                  "initialisation's transient) [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--max-dt", args->max_dt_s, "max time difference to match poses [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option(
         "--rpe-lengths", args->rpe_lengths_m,
         "RPE segment lengths in metres, comma separated (default: 10,20,..,50 % of the path)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  cmd->add_option("--cr-max-position-m", args->cr_max_position_m,
                  "correct rate: max position error of a correct pose [m]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--cr-max-angle-deg", args->cr_max_angle_deg,
                  "correct rate: max orientation error of a correct pose [deg]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--plot", args->plot_path,
                  "write a picture (PNG) of the aligned trajectories and errors");
  cmd->add_option("--json", args->json_path, "write all figures as JSON");
  cmd->callback([args] { runEval(*args); });
}

}  // namespace adugs::app

#include "app/run_pipeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numeric>
#include <sstream>
#include <vector>

#include "app/pipeline/pipeline.h"
#include "app/run_config.h"
#include "app/run_report.h"
#include "app/source_lost.h"
#include "calib/calibration_verdict.h"
#include "data/input_error.h"
#include "data/sim/sim_scene.h"
#include "vio/estimator/sliding_window_estimator.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}

vio::ImuPreintegrationOptions imuOptions(const data::ImuNoise& noise) {
  vio::ImuPreintegrationOptions o;
  o.gyro_noise_density = noise.gyro_noise_density;
  o.accel_noise_density = noise.accel_noise_density;
  o.gyro_random_walk = noise.gyro_random_walk;
  o.accel_random_walk = noise.accel_random_walk;
  return o;
}

PipelineOptions pipelineOptions(const RunConfig& config, const data::OpenedSequence& sequence,
                                const PipelineRunArgs& a, const std::string& trajectory_path) {
  PipelineOptions o;
  o.masking = a.mask.masking;
  o.masking.mask_dir = sequence.mask_dir;
  o.masking.objects_path = sequence.objects_path;
  o.masking.masker = config.dynamic;
  if (a.mask.detect_every > 0) o.masking.masker.detect_every = a.mask.detect_every;
  if (!o.masking.masker.track && o.masking.masker.detect_every != 1)
    throw data::InputError("--detect-every", 0, "detect_every",
                           "detecting every n-th frame needs the tracker (dynamic: tracker: sort)");
  o.tracker = config.tracker;
  o.estimate = sequence.has_imu;
  o.estimator = config.estimator;
  // The solver's wall-clock guard is for live sources, whose entrance drops frames when the
  // estimator falls behind; in playback it would only make the poses depend on the machine's load.
  if (!sequence.source->isLive()) o.estimator.max_solver_time_s = std::numeric_limits<double>::infinity();
  o.imu = imuOptions(sequence.imu_noise);
  o.trajectory_path = trajectory_path;
  o.view.overlay_path = a.overlay;
  o.view.fps = sequence.camera.rate_hz > 0 ? sequence.camera.rate_hz : 20.0;
  o.view.window = a.window;
  o.view.title = "adugs " + a.command;
  o.frame_queue = static_cast<size_t>(config.pipeline.frame_queue);
  o.test_estimator_delay_ms = config.pipeline.test_estimator_delay_ms;
  o.status_prefix = a.command;
  o.status = !a.quiet;
  return o;
}

// The lines of summary.yaml after writeRunOutputs' common ones.
std::string summaryLines(const Pipeline& pipeline, const PipelineResult& r, const data::OpenedSequence& sequence,
                         const RunConfig& config, const PipelineRunArgs& a, const std::vector<std::string>& weak) {
  const PipelineStats& s = pipeline.stats();
  const data::SourceCounts& counts = r.source_counts;
  std::ostringstream out;
  out << "source: \"" << sequence.source->description() << "\"\n"
      << "calibration: \"" << sequence.calibration_from << "\"\n"
      << calib::calibrationWeakYamlLine(weak);
  out << "late_messages_dropped: " << counts.late_dropped << "\n"
      << "imu_samples_dropped: " << counts.imu_dropped << "\n"
      << "unmatched_gyro_samples: " << counts.unmatched_gyro << "\n"
      << "gt_duplicates_in_bag: " << sequence.gt_duplicates_dropped << "\n"
      << "mask: " << maskSourceName(a.mask.masking.source) << "\n"
      << "motion_cue: "
      << (usesMotionCue(a.mask.masking) ? "true" : "false")
      << "  # class-free boxes of points moving against the camera's motion (--mask motion, --motion-cue)\n"
      << "threads: " << r.threads << " (acquisition, detection, masking, front-end, "
      << (pipeline.estimator() ? "estimator" : "statistics (vision only)") << (r.threads > 5 ? ", view" : "") << ")\n";
  if (const vio::SlidingWindowEstimator* estimator = pipeline.estimator()) {
    const vio::EstimatorStats& es = estimator->stats();
    out << "keyframes: " << es.keyframes << "\n"
        << "resets: " << es.resets << "\n"
        << "resets_continued: " << es.resets_continued
        << "  # re-initialised where the IMU carried the last state (estimator: reset_dead_reckoning_max_s)\n"
        << "frames_without_imu: " << es.frames_without_imu << "\n"
        << "outliers_rejected: " << es.outliers_rejected << "\n"
        << "init_kind: " << (es.init_kind.empty() ? "none" : es.init_kind) << "\n"
        << "init_time_s: " << (es.init_t_ns >= 0 ? data::nsToSec(es.init_t_ns - r.first_t_ns) : -1.0) << "\n"
        << "init_scale_relative_std: " << es.init_scale_relative_std
        << "  # the visual-inertial alignment's scale uncertainty (-1: none or static)\n"
        << "init_refused_uncertain_scale: " << es.init_refused_uncertain_scale << "\n";
    const double guard_s = estimator->options().max_solver_time_s;  // playback: lifted (pipelineOptions)
    if (std::isfinite(guard_s))
      out << "solver_time_guard_s: " << guard_s << "\n";
    else
      out << "solver_time_guard_s: none  # playback: no time limit on a solve, whatever the load\n";
    out << "solves_cut_by_time: " << es.solves_cut_by_time << "\n";
    const double per_solve = 1.0 / std::max(1, es.solves);
    out << "solver_steps_per_solve: " << es.solver_iterations * per_solve << "  # tried, of which accepted "
        << es.solver_successful * per_solve << "; at most max_iterations (" << estimator->options().max_iterations
        << "), fewer when converged\n";
    out << "accel_noise_density: " << estimator->imuOptions().accel_noise_density
        << "  # m/s^2/sqrt(Hz) in the preintegration: the IMU calibration's " << sequence.imu_noise.accel_noise_density
        << " x accel_noise_inflation " << estimator->options().accel_noise_inflation << "\n";
    out << "first_estimate_jacobians: " << (estimator->options().first_estimate_jacobians ? "true" : "false")
        << "\n"
        << "prior_yaw_information_median: " << median(es.prior_yaw_information)
        << "  # rad^-2 along the unobservable turn about gravity, after each marginalisation (0 when consistent)\n";
    const Eigen::Isometry3d& T = estimator->extrinsic();
    const Eigen::Isometry3d& T0 = sequence.camera.T_B_C;
    const Eigen::Quaterniond q(T.rotation());
    out << "extrinsic_estimated: " << (config.estimator.estimate_extrinsic ? "true" : "false") << "\n"
        << "extrinsic_T_B_C: [" << T.translation().x() << ", " << T.translation().y() << ", " << T.translation().z()
        << ", " << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]  # tx ty tz qx qy qz qw\n"
        << "extrinsic_change_deg: "
        << Eigen::AngleAxisd(T0.rotation().transpose() * T.rotation()).angle() * 180.0 / M_PI << "\n"
        << "extrinsic_change_m: " << (T.translation() - T0.translation()).norm() << "\n"
        << "time_offset_estimated: " << (config.estimator.estimate_time_offset ? "true" : "false") << "\n"
        << "time_offset_s: " << estimator->timeOffset() << "  # t_imu = t_cam + td\n";
    if (!es.last_failure.empty()) out << "last_failure: \"" << es.last_failure << "\"\n";
    if (es.init_t_ns < 0 && !es.last_init_failure.empty())
      out << "last_init_failure: \"" << es.last_init_failure << "\"\n";
    out << "timing_ms:\n"
        << "  frontend_median: " << median(s.frontend_ms) << "\n"
        << "  frontend_mean: " << mean(s.frontend_ms) << "\n"
        << "  backend_median: " << median(s.backend_ms) << "\n"
        << "  backend_mean: " << mean(s.backend_ms) << "\n"
        << "  solve_median: " << median(es.solve_ms) << "\n"
        << "  solve_mean: " << mean(es.solve_ms) << "\n"
        << "  marginalization_median: " << median(es.marginalization_ms) << "\n"
        << "  marginalization_mean: " << mean(es.marginalization_ms) << "\n";
  } else {
    out << "timing_ms:\n"
        << "  frontend_median: " << median(s.frontend_ms) << "\n"
        << "  frontend_mean: " << mean(s.frontend_ms) << "\n";
  }
  out << "  dynamic_mask_median: " << median(s.mask_ms) << "  # detector + SORT, segmentation, refinement\n"
      << "  detection_median: " << median(s.detect_ms) << "  # the frames the detector ran on\n"
      << "  segmentation_median: " << median(s.segment_ms) << "  # SORT, segmentation, refinement\n"
      << "  latency_median: " << median(s.latency_ms) << "  # source -> estimated\n"
      << "dynamic_features_dropped_per_frame: " << mean(s.dynamic_drop) << "\n"
      << "masked_image_fraction: " << mean(s.masked_fraction) << "\n";
  if (usesMotionCue(a.mask.masking))
    out << "objects_seen_static: " << s.objects_seen_static
        << "  # tracked objects the motion cue judged static, then not masked (dynamic: static_after_frames)\n";
  if (s.exact_pixels > 0)  // --mask detector on a sequence with the simulator's exact masks
    out << "dynamic_mask_vs_exact: {recall: " << s.exact_covered / s.exact_pixels
        << ", precision: " << (s.masked_pixels > 0 ? s.exact_covered / s.masked_pixels : 0.0) << "}\n";
  if (!s.exact_by_class.empty()) {  // the simulator's movers, per class (COCO ids of objects0/gt.txt)
    // The simulator's names for its classes' COCO ids.
    const auto name = [](int coco) -> std::string {
      for (data::SimObjectClass c : {data::SimObjectClass::kPerson, data::SimObjectClass::kCar, data::SimObjectClass::kBus})
        if (data::cocoClassId(c) == coco) return data::toString(c);
      return "coco_" + std::to_string(coco);
    };
    out << "dynamic_mask_recall_per_class: {";
    const char* separator = "";
    for (const auto& [cls, pixels] : s.exact_by_class) {
      out << separator << name(cls) << ": " << (pixels.first > 0 ? pixels.second / pixels.first : 0.0);
      separator = ", ";
    }
    out << "}  # of the exact pixels inside each class's boxes (objects0/gt.txt)\n";
  }
  if (s.exact_pixels > 0 && s.masked_motion + s.masked_detector > 0) {  // both cues: each one's share
    const auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
    out << "dynamic_mask_vs_exact_per_cue: {detector: {recall: " << ratio(s.exact_covered_detector, s.exact_pixels)
        << ", precision: " << ratio(s.exact_covered_detector, s.masked_detector)
        << "}, motion: {recall: " << ratio(s.exact_covered_motion, s.exact_pixels)
        << ", precision: " << ratio(s.exact_covered_motion, s.masked_motion)
        << "}}  # the mask inside each cue's boxes\n";
  }
  out << "features_per_frame: " << mean(s.features) << "\n"
      << "command: " << a.command << "\n"
      << "live: " << (r.live ? "true" : "false") << "\n"
      << "end: " << toString(r.end) << "\n";
  if (!r.why.empty()) {
    std::string why = r.why;
    std::replace(why.begin(), why.end(), '"', '\'');
    std::replace(why.begin(), why.end(), '\n', ' ');
    out << "end_detail: \"" << why << "\"\n";
  }
  out << "frames_acquired: " << r.frames_acquired << "\n"
      << "frames_dropped: " << r.frames_dropped << "  # live policy: the oldest waiting frame when the stages fall behind\n"
      << "frames_lost_by_source: " << counts.frames_lost << "\n"
      << "imu_samples_to_estimator: " << s.imu_to_estimator << "\n"
      << "imu_samples_after_last_frame: " << r.imu_after_last_frame << "\n";
  out << "cpu_s: " << r.cpu_s << "  # user + system, every thread\n"
      << "cpu_per_sequence_s: " << (s.sequence_s > 0 ? r.cpu_s / s.sequence_s : 0.0)
      << "  # below the machine's cores: it could keep up if the stages overlap\n"
      << "stage_thread_cpu_s: {";
  for (size_t i = 0; i < r.stage_cpu_s.size(); ++i)
    out << (i ? ", " : "") << r.stage_cpu_s[i].first << ": " << r.stage_cpu_s[i].second;
  out << "}  # each stage's own thread (library worker threads not included)\n";
  if (r.threads > 5) out << "view_frames_skipped: " << s.view_frames_skipped << "  # live: the view never holds the pipeline back\n";
  return out.str();
}

}  // namespace

void runPipeline(data::OpenedSequence& sequence, const PipelineRunArgs& a) {
  std::string config_used;
  const RunConfig config = runConfigFor(a.config_path, sequence, &config_used);
  if (!a.quiet) std::cerr << a.command << ": config " << config_used << "\n";
  // Said even with -q: a weak calibration limits every pose of the run.
  const std::vector<std::string> weak = calib::filesMarkedWeak(sequence.calibration_files);
  for (const std::string& file : weak)
    std::cerr << "WARNING: " << a.command << ": " << file
              << ": adugs calib marked this calibration WEAK (the reasons and what to record next are at the top "
                 "of the file); the poses are only as good as it\n";
  fs::create_directories(a.out_dir);
  const std::string traj_path = sequence.has_imu ? (fs::path(a.out_dir) / "trajectory.tum").string() : "";
  Pipeline pipeline(*sequence.source, sequence.camera, pipelineOptions(config, sequence, a, traj_path));
  const PipelineResult r = pipeline.run();

  const PipelineStats& s = pipeline.stats();
  RunStats stats;
  stats.command = a.command;
  stats.frames = s.frames;
  stats.poses = s.poses;
  stats.imu_samples = r.imu_acquired;
  stats.skipped_frames = r.source_counts.skipped_frames;
  stats.sequence_s = s.sequence_s;
  stats.wall_s = r.wall_s;
  stats.extra_summary = "config: \"" + config_used + "\"\n" + summaryLines(pipeline, r, sequence, config, a, weak);
  if (const vio::SlidingWindowEstimator* estimator = pipeline.estimator())
    stats.relative_poses = &estimator->stats().relative_poses;
  if (r.end == PipelineResult::End::kStopped && !a.quiet)
    std::cerr << a.command << ": stopped (" << r.why << ") after " << s.frames
              << " frames; the frames already inside were finished and every output is written\n";
  else if (r.end == PipelineResult::End::kEndOfSource && r.live && !a.quiet)
    std::cerr << a.command << ": the source ended (" << (r.why.empty() ? sequence.source->description() : r.why)
              << ") after " << r.frames_acquired << " frames; every output is written\n";
  writeRunOutputs(a.out_dir, sequence.has_imu ? "vio" : "none", traj_path,
                  r.end == PipelineResult::End::kError ? "" : sequence.gt_path, stats);
  if (r.error) std::rethrow_exception(r.error);
  if (r.end == PipelineResult::End::kEndOfSource && r.live && !r.why.empty())
    throw SourceLost("the live source ended by itself: " + r.why + "; every output is written in " + a.out_dir);
}

}  // namespace adugs::app

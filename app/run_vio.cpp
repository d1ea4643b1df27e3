#include "app/run_vio.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <sstream>
#include <thread>

#include "data/input_error.h"
#include "app/run_config.h"
#include "app/run_report.h"
#include "app/vio_frontend_stage.h"
#include "data/camera_model.h"
#include "data/trajectory_io.h"
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

}  // namespace

void runVio(const VioRunArgs& a) {
  const RunConfig config = loadRunConfig(a.config_path);
  data::OpenedSequence sequence = data::openSequence(a.playback, a.out_dir);
  data::SequenceSource& source = *sequence.source;
  const std::string& gt_path = sequence.gt_path;

  const data::CameraModel camera(sequence.camera);
  tracking::DynamicMaskerOptions masker = config.dynamic;
  if (a.detect_every > 0) masker.detect_every = a.detect_every;
  if (!masker.track && masker.detect_every != 1)
    throw data::InputError("--detect-every", 0, "detect_every", "detecting every n-th frame needs the tracker (dynamic: tracker: sort)");
  FrontEndStage front_end(
      source, config.tracker, camera, sequence.camera.T_B_C,
      {a.mask, sequence.mask_dir, a.detector_model, a.segmenter, a.sam_encoder, a.sam_decoder,
       a.detector_config, masker, a.overlay});
  const double focal = 0.5 * (camera.fx() + camera.fy());
  vio::SlidingWindowEstimator estimator(config.estimator, focal, sequence.camera.T_B_C,
                                        imuOptions(sequence.imu_noise));

  fs::create_directories(a.out_dir);
  const std::string traj_path = (fs::path(a.out_dir) / "trajectory.tum").string();
  data::TumTrajectoryWriter writer(traj_path);

  // Two threads: the front-end (decoding, masks, KLT) runs one frame ahead of the estimator,
  // which works here on the calling thread.
  Channel<TrackedFrame> frames(2);
  Channel<Eigen::Vector3d> gyro_biases;
  std::exception_ptr front_end_error;
  std::thread front_end_thread([&] {
    try {
      front_end.run(frames, gyro_biases);
    } catch (...) {
      front_end_error = std::current_exception();
      frames.close();
    }
  });
  auto stop_front_end = [&] {
    frames.close();
    gyro_biases.close();
    front_end_thread.join();
  };

  RunStats stats;
  std::vector<double> frontend_ms, backend_ms, mask_ms, dynamic_drop, masked_fraction;
  double exact_pixels = 0, exact_covered = 0, masked_pixels = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  TrackedFrame f;
  try {
    while (frames.pop(&f)) {
      ++stats.frames;
      stats.sequence_s = f.sequence_s;
      frontend_ms.push_back(f.frontend_ms);
      dynamic_drop.push_back(f.dropped_dynamic);
      if (f.mask_ms >= 0) {
        mask_ms.push_back(f.mask_ms);
        masked_fraction.push_back(f.masked_fraction);
        exact_pixels += f.exact_pixels;
        exact_covered += f.exact_covered;
        masked_pixels += f.masked_pixels;
      }
      for (const data::ImuSample& s : f.imu) estimator.addImu(s);
      const auto t0 = std::chrono::steady_clock::now();
      const auto state = estimator.addFrame(f.features);
      backend_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      gyro_biases.push(estimator.gyroBias());
      if (state) {
        data::StampedPose p;
        p.t_ns = state->t_ns;
        p.p_W_B = state->p_W_B;
        p.q_W_B = state->q_W_B;
        writer.write(p);
        ++stats.poses;
      }
      if (!a.quiet && stats.frames % 100 == 0)
        std::cerr << "run: " << stats.frames << " frames, " << stats.sequence_s << " s, "
                  << (estimator.initialized() ? "tracking" : "initialising") << ", resets "
                  << estimator.stats().resets << "\n"
                  << std::flush;
    }
  } catch (...) {
    stop_front_end();
    throw;
  }
  stop_front_end();
  if (front_end_error) std::rethrow_exception(front_end_error);
  writer.close();
  stats.imu_samples = front_end.imuSamples();
  const data::SourceCounts counts = source.counts();
  stats.skipped_frames = counts.skipped_frames;
  stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  const vio::EstimatorStats& es = estimator.stats();
  const int64_t first_t = front_end.firstTimeNs();
  std::ostringstream extra;
  extra << "source: \"" << source.description() << "\"\n"
        << "calibration: \"" << sequence.calibration_from << "\"\n"
        << "late_messages_dropped: " << counts.late_dropped << "\n"
        << "imu_samples_dropped: " << counts.imu_dropped << "\n"
        << "unmatched_gyro_samples: " << counts.unmatched_gyro << "\n"
        << "gt_duplicates_in_bag: " << sequence.gt_duplicates_dropped << "\n"
        << "mask: " << a.mask << "\n"
        << "threads: 2 (front-end, estimator)\n"
        << "keyframes: " << es.keyframes << "\n"
        << "resets: " << es.resets << "\n"
        << "frames_without_imu: " << es.frames_without_imu << "\n"
        << "outliers_rejected: " << es.outliers_rejected << "\n"
        << "init_kind: " << (es.init_kind.empty() ? "none" : es.init_kind) << "\n"
        << "init_time_s: " << (es.init_t_ns >= 0 ? data::nsToSec(es.init_t_ns - first_t) : -1.0)
        << "\n";
  {
    const Eigen::Isometry3d& T = estimator.extrinsic();
    const Eigen::Isometry3d& T0 = sequence.camera.T_B_C;
    const Eigen::Quaterniond q(T.rotation());
    extra << "extrinsic_estimated: " << (config.estimator.estimate_extrinsic ? "true" : "false")
          << "\n"
          << "extrinsic_T_B_C: [" << T.translation().x() << ", " << T.translation().y() << ", "
          << T.translation().z() << ", " << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w()
          << "]  # tx ty tz qx qy qz qw\n"
          << "extrinsic_change_deg: "
          << Eigen::AngleAxisd(T0.rotation().transpose() * T.rotation()).angle() * 180.0 / M_PI
          << "\n"
          << "extrinsic_change_m: " << (T.translation() - T0.translation()).norm() << "\n";
  }
  extra << "time_offset_estimated: " << (config.estimator.estimate_time_offset ? "true" : "false")
        << "\n"
        << "time_offset_s: " << estimator.timeOffset() << "  # t_imu = t_cam + td\n";
  if (!es.last_failure.empty()) extra << "last_failure: \"" << es.last_failure << "\"\n";
  if (es.init_t_ns < 0 && !es.last_init_failure.empty())
    extra << "last_init_failure: \"" << es.last_init_failure << "\"\n";
  extra << "timing_ms:\n"
        << "  frontend_median: " << median(frontend_ms) << "\n"
        << "  frontend_mean: " << mean(frontend_ms) << "\n"
        << "  backend_median: " << median(backend_ms) << "\n"
        << "  backend_mean: " << mean(backend_ms) << "\n"
        << "  solve_median: " << median(es.solve_ms) << "\n"
        << "  solve_mean: " << mean(es.solve_ms) << "\n"
        << "  marginalization_median: " << median(es.marginalization_ms) << "\n"
        << "  marginalization_mean: " << mean(es.marginalization_ms) << "\n"
        << "  dynamic_mask_median: " << median(mask_ms) << "\n"
        << "dynamic_features_dropped_per_frame: " << mean(dynamic_drop) << "\n"
        << "masked_image_fraction: " << mean(masked_fraction) << "\n";
  if (exact_pixels > 0)  // --mask detector on a sequence with the simulator's exact masks
    extra << "dynamic_mask_vs_exact: {recall: " << exact_covered / exact_pixels
          << ", precision: " << (masked_pixels > 0 ? exact_covered / masked_pixels : 0.0) << "}\n";
  stats.extra_summary = extra.str();
  writeRunOutputs(a.out_dir, "vio", traj_path, gt_path, stats);
}

}  // namespace adugs::app

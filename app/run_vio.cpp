#include "app/run_vio.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "app/run_config.h"
#include "app/run_report.h"
#include "data/euroc_reader.h"
#include "data/input_error.h"
#include "data/trajectory_io.h"
#include "tracking/dynamic_masker.h"
#include "tracking/segmenter_factory.h"
#include "tracking/yolox_detector.h"
#include "vio/camera_model.h"
#include "vio/feature_tracker.h"
#include "vio/sliding_window_estimator.h"

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

// The simulator's ground-truth mask of a frame: mav0/mask0/data/<image file name>.
cv::Mat loadGroundTruthMask(const std::string& mav_dir, const data::Frame& frame) {
  const std::string path =
      (fs::path(mav_dir) / "mask0" / "data" / fs::path(frame.path).filename()).string();
  cv::Mat mask = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mask.empty())
    throw data::InputError(path, 0, "mask", "missing or unreadable dynamic mask (--mask gt)");
  if (mask.size() != frame.image.size())
    throw data::InputError(
        path, 0, "mask",
        "mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", the image " +
            std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows));
  return mask;
}

}  // namespace

void runVio(const VioRunArgs& a) {
  const RunConfig config = loadRunConfig(a.config_path);
  data::EurocReaderOptions reader_options;
  reader_options.skip_bad_frames = a.skip_bad_frames;
  data::EurocReader reader(a.path, reader_options);
  const std::string gt_path = a.gt_path.empty() ? reader.groundTruthPath() : a.gt_path;

  const vio::CameraModel camera(reader.camera());
  vio::FeatureTracker tracker(config.tracker, camera);
  vio::ImuPreintegrationOptions imu_options;
  const data::ImuNoise& noise = reader.imuNoise();
  imu_options.gyro_noise_density = noise.gyro_noise_density;
  imu_options.accel_noise_density = noise.accel_noise_density;
  imu_options.gyro_random_walk = noise.gyro_random_walk;
  imu_options.accel_random_walk = noise.accel_random_walk;
  const double focal = 0.5 * (camera.fx() + camera.fy());
  vio::SlidingWindowEstimator estimator(config.estimator, focal, reader.camera().T_B_C,
                                        imu_options);
  const Eigen::Matrix3d R_B_C = reader.camera().T_B_C.rotation();

  // The dynamic-object stage of the paper: detector -> SORT -> box segmentation -> refinement.
  std::unique_ptr<tracking::YoloxDetector> detector;
  std::unique_ptr<tracking::DynamicMasker> masker;
  if (a.mask == "detector") {
    if (a.detector_model.empty())
      throw data::InputError("--detector-model", 0, "detector_model",
                             "--mask detector needs a YOLOX ONNX model");
    detector = std::make_unique<tracking::YoloxDetector>(a.detector_model);
    masker = std::make_unique<tracking::DynamicMasker>(
        tracking::DynamicMaskerOptions{},
        tracking::makeBoxSegmenter(a.segmenter, a.sam_encoder, a.sam_decoder));
  }

  fs::create_directories(a.out_dir);
  const std::string traj_path = (fs::path(a.out_dir) / "trajectory.tum").string();
  data::TumTrajectoryWriter writer(traj_path);

  RunStats stats;
  std::vector<double> frontend_ms, backend_ms, mask_ms, dynamic_drop, masked_fraction;
  const auto wall_start = std::chrono::steady_clock::now();
  data::Measurement m;
  int64_t first_t = -1;
  while (reader.next(m)) {
    if (first_t < 0) first_t = m.timeNs();
    if (m.isImu()) {
      ++stats.imu_samples;
      estimator.addImu(m.imu);
      continue;
    }
    ++stats.frames;
    stats.sequence_s = data::nsToSec(m.frame.t_ns - first_t);
    cv::Mat mask;
    if (a.mask == "gt") mask = loadGroundTruthMask(reader.mavDir(), m.frame);
    if (masker) {
      const auto t_mask = std::chrono::steady_clock::now();
      const tracking::DynamicMaskResult r =
          masker->process(m.frame.image, detector->detect(m.frame.image));
      mask_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_mask)
              .count());
      masked_fraction.push_back(r.masked_fraction);
      mask = r.mask;
    }
    const Eigen::Matrix3d R_B = estimator.rotationSinceLastFrame(m.frame.t_ns).toRotationMatrix();
    tracker.setPredictedRotation(R_B_C.transpose() * R_B * R_B_C);
    auto t0 = std::chrono::steady_clock::now();
    const vio::FrameFeatures features = tracker.trackFrame(m.frame.t_ns, m.frame.image, mask);
    frontend_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    dynamic_drop.push_back(tracker.lastStats().dropped_dynamic);
    t0 = std::chrono::steady_clock::now();
    const auto state = estimator.addFrame(features);
    backend_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
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
  writer.close();
  stats.skipped_frames = reader.skippedFrames();
  stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  const vio::EstimatorStats& es = estimator.stats();
  std::ostringstream extra;
  extra << "mask: " << a.mask << "\n"
        << "keyframes: " << es.keyframes << "\n"
        << "resets: " << es.resets << "\n"
        << "init_kind: " << (es.init_kind.empty() ? "none" : es.init_kind) << "\n"
        << "init_time_s: " << (es.init_t_ns >= 0 ? data::nsToSec(es.init_t_ns - first_t) : -1.0)
        << "\n";
  if (!es.last_failure.empty()) extra << "last_failure: \"" << es.last_failure << "\"\n";
  if (es.init_t_ns < 0 && !es.last_init_failure.empty())
    extra << "last_init_failure: \"" << es.last_init_failure << "\"\n";
  extra << "timing_ms:\n"
        << "  frontend_median: " << median(frontend_ms) << "\n"
        << "  frontend_mean: " << mean(frontend_ms) << "\n"
        << "  backend_median: " << median(backend_ms) << "\n"
        << "  backend_mean: " << mean(backend_ms) << "\n"
        << "  solve_median: " << median(es.solve_ms) << "\n"
        << "  marginalization_median: " << median(es.marginalization_ms) << "\n"
        << "  dynamic_mask_median: " << median(mask_ms) << "\n"
        << "dynamic_features_dropped_per_frame: " << mean(dynamic_drop) << "\n"
        << "masked_image_fraction: " << mean(masked_fraction) << "\n";
  stats.extra_summary = extra.str();
  writeRunOutputs(a.out_dir, "vio", traj_path, gt_path, stats);
}

}  // namespace adugs::app

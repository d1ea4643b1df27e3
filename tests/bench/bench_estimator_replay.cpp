// The estimator alone on recorded front-end output, for profiling and for estimator-only
// variations without decoding and tracking images every time.
//
//   bench_estimator_replay record SEQ_DIR --out FEATURES.bin [--config YAML] [--duration S]
//       plays an EuRoC folder through the front-end (KLT prediction from the gyro with the
//       estimator's bias, as `adugs run`) and the estimator, and writes every frame's IMU samples
//       and tracked features to FEATURES.bin (with the camera's focal length, T_B_C and the IMU
//       noise figures).
//   bench_estimator_replay replay FEATURES.bin [--config YAML] [--out TRAJ.tum] [--frames N]
//                          [--quiet] [--no-time-limit]
//       feeds them (the first N frames) to the estimator alone and prints the back-end time per frame (median, mean,
//       p90), the solve and marginalisation times, and writes the trajectory.
// --config reads the `estimator:` (and, when recording, `tracker:`) map of a run config.
// The front-end's KLT prediction depends on the estimator's gyro bias, so a replay with other
// estimator options sees the features of the recording configuration: use it to profile
// (valgrind --tool=callgrind bench_estimator_replay replay ...) and to compare estimator
// options, and confirm accuracy changes with `adugs run` (scripts/bench_vio.sh).
// --no-time-limit lifts the solver's wall-clock guard (max_solver_time_s, at most 10 s in a config)
// entirely: under callgrind a window-15 solve can take longer than 10 s of wall time, and a solve
// cut by the clock would make instruction counts depend on the machine's load.
// Not a Google Benchmark (a measurement tool): figures go to doc/estimator.md and doc/results.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/camera_model.h"
#include "data/formats/trajectory_io.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "data/sources/euroc_reader.h"
#include "vio/estimator/sliding_window_estimator.h"
#include "vio/frontend/feature_tracker.h"
#include "vio/imu/gyro_rotation_predictor.h"

using namespace adugs;

namespace {

constexpr uint32_t kMagic = 0x41445246;  // "ADRF"
constexpr uint32_t kVersion = 1;

struct Recording {
  double focal_px = 0;
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();
  vio::ImuPreintegrationOptions imu;
  struct Frame {
    std::vector<data::ImuSample> imu;  // since the previous frame
    vio::FrameFeatures features;
  };
  std::vector<Frame> frames;
};

template <typename T>
void put(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
T get(std::istream& in) {
  T v{};
  in.read(reinterpret_cast<char*>(&v), sizeof(T));
  if (!in) throw std::runtime_error("truncated recording");
  return v;
}

void writeRecording(const Recording& r, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot write");
  put(out, kMagic);
  put(out, kVersion);
  put(out, r.focal_px);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) put(out, r.T_B_C.matrix()(i, j));
  put(out, r.imu.gyro_noise_density);
  put(out, r.imu.accel_noise_density);
  put(out, r.imu.gyro_random_walk);
  put(out, r.imu.accel_random_walk);
  put(out, static_cast<uint64_t>(r.frames.size()));
  for (const Recording::Frame& f : r.frames) {
    put(out, static_cast<uint64_t>(f.imu.size()));
    for (const data::ImuSample& s : f.imu) {
      put(out, s.t_ns);
      for (int i = 0; i < 3; ++i) put(out, s.gyro(i));
      for (int i = 0; i < 3; ++i) put(out, s.accel(i));
    }
    const vio::FrameFeatures& ff = f.features;
    put(out, ff.t_ns);
    put(out, static_cast<uint64_t>(ff.size()));
    for (size_t k = 0; k < ff.size(); ++k) {
      put(out, ff.ids[k]);
      put(out, ff.pixels[k].x);
      put(out, ff.pixels[k].y);
      put(out, ff.prev_pixels[k].x);
      put(out, ff.prev_pixels[k].y);
      put(out, ff.normalized[k].x());
      put(out, ff.normalized[k].y());
      put(out, ff.track_counts[k]);
      put(out, ff.velocities[k].x());
      put(out, ff.velocities[k].y());
    }
  }
  if (!out) throw std::runtime_error(path + ": write failed");
}

Recording readRecording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  if (get<uint32_t>(in) != kMagic || get<uint32_t>(in) != kVersion)
    throw std::runtime_error(path + ": not a recording of this version");
  Recording r;
  r.focal_px = get<double>(in);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.T_B_C.matrix()(i, j) = get<double>(in);
  r.imu.gyro_noise_density = get<double>(in);
  r.imu.accel_noise_density = get<double>(in);
  r.imu.gyro_random_walk = get<double>(in);
  r.imu.accel_random_walk = get<double>(in);
  r.frames.resize(get<uint64_t>(in));
  for (Recording::Frame& f : r.frames) {
    f.imu.resize(get<uint64_t>(in));
    for (data::ImuSample& s : f.imu) {
      s.t_ns = get<int64_t>(in);
      for (int i = 0; i < 3; ++i) s.gyro(i) = get<double>(in);
      for (int i = 0; i < 3; ++i) s.accel(i) = get<double>(in);
    }
    vio::FrameFeatures& ff = f.features;
    ff.t_ns = get<int64_t>(in);
    const size_t n = get<uint64_t>(in);
    for (size_t k = 0; k < n; ++k) {
      ff.ids.push_back(get<int64_t>(in));
      const float x = get<float>(in), y = get<float>(in), px = get<float>(in), py = get<float>(in);
      ff.pixels.emplace_back(x, y);
      ff.prev_pixels.emplace_back(px, py);
      const double nx = get<double>(in), ny = get<double>(in);
      ff.normalized.emplace_back(nx, ny);
      ff.track_counts.push_back(get<int>(in));
      const double vx = get<double>(in), vy = get<double>(in);
      ff.velocities.emplace_back(vx, vy);
    }
  }
  return r;
}

void readConfig(const std::string& path, vio::FeatureTrackerOptions* tracker,
                vio::EstimatorOptions* estimator) {
  if (path.empty()) return;
  data::YamlOptionsReader r = data::YamlOptionsReader::fromFile(path);
  if (r.has("tracker")) {
    data::YamlOptionsReader t = r.child("tracker");
    vio::readFeatureTrackerOptions(t, tracker);
    t.finish();
  }
  if (r.has("estimator")) {
    data::YamlOptionsReader e = r.child("estimator");
    vio::readEstimatorOptions(e, estimator);
    e.finish();
  }
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

int record(const std::string& dir, const std::string& out_path, const std::string& config,
           double duration_s) {
  data::EurocReader reader(dir);
  const data::CameraModel camera(reader.camera());
  vio::FeatureTrackerOptions tracker_options;
  vio::EstimatorOptions estimator_options;
  readConfig(config, &tracker_options, &estimator_options);
  vio::FeatureTracker tracker(tracker_options, camera);
  Recording rec;
  rec.focal_px = 0.5 * (camera.fx() + camera.fy());
  rec.T_B_C = reader.camera().T_B_C;
  rec.imu.gyro_noise_density = reader.imuNoise().gyro_noise_density;
  rec.imu.accel_noise_density = reader.imuNoise().accel_noise_density;
  rec.imu.gyro_random_walk = reader.imuNoise().gyro_random_walk;
  rec.imu.accel_random_walk = reader.imuNoise().accel_random_walk;
  vio::SlidingWindowEstimator estimator(estimator_options, rec.focal_px, rec.T_B_C, rec.imu);
  vio::GyroRotationPredictor gyro;
  const Eigen::Matrix3d R_B_C = rec.T_B_C.rotation();
  data::Measurement m;
  Recording::Frame frame;
  int64_t first_t = -1, previous_t = -1;
  while (reader.next(m)) {
    if (first_t < 0) first_t = m.timeNs();
    if (duration_s > 0 && m.timeNs() - first_t > data::secToNs(duration_s)) break;
    if (m.isImu()) {
      gyro.addImu(m.imu);
      estimator.addImu(m.imu);
      frame.imu.push_back(m.imu);
      continue;
    }
    if (previous_t >= 0) {
      const Eigen::Matrix3d R_B =
          gyro.rotation(previous_t, m.frame.t_ns, estimator.gyroBias()).toRotationMatrix();
      tracker.setPredictedRotation(R_B_C.transpose() * R_B * R_B_C);
      gyro.dropBefore(m.frame.t_ns);
    }
    frame.features = tracker.trackFrame(m.frame.t_ns, m.frame.image);
    estimator.addFrame(frame.features);
    rec.frames.push_back(std::move(frame));
    frame = Recording::Frame{};
    previous_t = m.frame.t_ns;
  }
  writeRecording(rec, out_path);
  std::cout << "recorded " << rec.frames.size() << " frames to " << out_path << "\n";
  return 0;
}

int replay(const std::string& path, const std::string& config, const std::string& traj_path,
           int max_frames, bool quiet, bool no_time_limit) {
  const Recording rec = readRecording(path);
  vio::FeatureTrackerOptions unused;
  vio::EstimatorOptions options;
  readConfig(config, &unused, &options);
  if (no_time_limit) options.max_solver_time_s = std::numeric_limits<double>::infinity();
  vio::SlidingWindowEstimator estimator(options, rec.focal_px, rec.T_B_C, rec.imu);
  std::unique_ptr<data::TumTrajectoryWriter> writer;
  if (!traj_path.empty()) writer = std::make_unique<data::TumTrajectoryWriter>(traj_path);
  std::vector<double> backend_ms;
  int played = 0;
  for (const Recording::Frame& f : rec.frames) {
    if (max_frames > 0 && played >= max_frames) break;
    ++played;
    for (const data::ImuSample& s : f.imu) estimator.addImu(s);
    const auto t0 = std::chrono::steady_clock::now();
    const auto state = estimator.addFrame(f.features);
    backend_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (state && writer) {
      data::StampedPose p;
      p.t_ns = state->t_ns;
      p.p_W_B = state->p_W_B;
      p.q_W_B = state->q_W_B;
      writer->write(p);
    }
  }
  if (writer) writer->close();
  const vio::EstimatorStats& s = estimator.stats();
  if (!quiet) {
    auto mean = [](const std::vector<double>& v) {
      return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    };
    std::printf("frames %d  keyframes %d  resets %d  outliers rejected %d\n", played,
                s.keyframes, s.resets, s.outliers_rejected);
    std::printf("solves %d: %.2f steps tried, %.2f accepted per solve; %d cut by the time limit\n",
                s.solves, s.solves ? double(s.solver_iterations) / s.solves : 0.0,
                s.solves ? double(s.solver_successful) / s.solves : 0.0, s.solves_cut_by_time);
    std::printf("back-end per frame  median %.2f  mean %.2f  p90 %.2f ms\n",
                percentile(backend_ms, 0.5), mean(backend_ms), percentile(backend_ms, 0.9));
    std::printf("solve               median %.2f  mean %.2f  p90 %.2f ms\n",
                percentile(s.solve_ms, 0.5), mean(s.solve_ms), percentile(s.solve_ms, 0.9));
    std::printf("marginalisation     median %.2f  mean %.2f  p90 %.2f ms\n",
                percentile(s.marginalization_ms, 0.5), mean(s.marginalization_ms),
                percentile(s.marginalization_ms, 0.9));
  }
  return 0;
}

int usage() {
  std::cerr << "usage: bench_estimator_replay record SEQ_DIR --out FEATURES.bin [--config YAML] "
               "[--duration S]\n"
               "       bench_estimator_replay replay FEATURES.bin [--config YAML] [--out TRAJ.tum] "
               "[--frames N] [--quiet] [--no-time-limit]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string mode = argv[1], input = argv[2];
  std::string out, config;
  double duration = 0;
  int frames = 0;
  bool quiet = false, no_time_limit = false;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--config" && i + 1 < argc) config = argv[++i];
    else if (a == "--duration" && i + 1 < argc) duration = std::stod(argv[++i]);
    else if (a == "--frames" && i + 1 < argc) frames = std::stoi(argv[++i]);
    else if (a == "--quiet") quiet = true;
    else if (a == "--no-time-limit") no_time_limit = true;
    else return usage();
  }
  try {
    if (mode == "record" && !out.empty()) return record(input, out, config, duration);
    if (mode == "replay") return replay(input, config, out, frames, quiet, no_time_limit);
  } catch (const data::InputError& e) {
    std::cerr << "bench_estimator_replay: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bench_estimator_replay: " << e.what() << "\n";
    return 1;
  }
  return usage();
}

// Front-end accuracy against the rendered truth of an `adugs sim` sequence (level none).
//
//   bench_track_accuracy SEQ_DIR [--frames N] [--no-anchors]
//                        [--vio klt|truth --out TRAJ.tum [--noise PX]]
//
// Each new feature gets its true 3-D point from the rendered depth at its first pixel (features
// on a depth edge are skipped); every later observation's error is the tracked pixel minus that
// point's projection at the true pose. Printed: the error by track age, and the change of a
// feature's error over 1, 10 and 30 frames - the drift a sliding window sees (a constant offset
// only moves the landmark) - split by whether the feature started within 5 px of a depth edge.
// --vio also runs the estimator on the tracks as they are (klt) or with each tracked position
// replaced by its true projection plus Gaussian noise (truth); compare the two with
//   adugs eval --est TRAJ.tum --gt SEQ_DIR/mav0/state_groundtruth_estimate0/data.csv
// Not a Google Benchmark (a measurement tool): figures go to doc/frontend.md and doc/results.md.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/camera_model.h"
#include "data/formats/trajectory_io.h"
#include "data/sim/sim_renderer.h"
#include "data/sim/sim_scene.h"
#include "data/sources/euroc_reader.h"
#include "vio/estimator/sliding_window_estimator.h"
#include "vio/frontend/feature_tracker.h"

using namespace adugs;

namespace {

// A top-level `key: value` of the sim.yaml the simulator writes.
std::string simInfo(const std::string& path, const std::string& key, const std::string& fallback = "") {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open (not an `adugs sim` sequence?)");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::string v = line.substr(key.size() + 1);
      v = v.substr(std::min(v.size(), v.find_first_not_of(' ')));
      return v.substr(0, v.find_first_of(" #"));
    }
  if (!fallback.empty()) return fallback;
  throw std::runtime_error(path + ": no '" + key + "'");
}

struct Percentiles {
  std::vector<double> v;
  void print(const char* label) {
    if (v.empty()) return;
    std::sort(v.begin(), v.end());
    std::printf("%-34s n %7zu  median %.3f  p90 %.3f  p99 %.3f px\n", label, v.size(), v[v.size() / 2],
                v[v.size() * 9 / 10], v[v.size() * 99 / 100]);
  }
};

// 1/z is affine in the image of a plane: interpolate it over the 2x2 pixel centres around uv.
// False near a depth edge (the four depths differ by more than 2 %) or the sky.
bool depthAt(const cv::Mat& depth, const Eigen::Vector2d& uv, double* z) {
  const int u = static_cast<int>(std::floor(uv.x())), v = static_cast<int>(std::floor(uv.y()));
  if (u < 0 || v < 0 || u + 1 >= depth.cols || v + 1 >= depth.rows) return false;
  const float d[4] = {depth.at<float>(v, u), depth.at<float>(v, u + 1), depth.at<float>(v + 1, u),
                      depth.at<float>(v + 1, u + 1)};
  const float lo = *std::min_element(d, d + 4), hi = *std::max_element(d, d + 4);
  if (!std::isfinite(hi) || hi - lo > 0.02f * lo) return false;
  const double a = uv.x() - u, b = uv.y() - v;
  *z = 1.0 / ((1 - a) * (1 - b) / d[0] + a * (1 - b) / d[1] + (1 - a) * b / d[2] + a * b / d[3]);
  return true;
}

bool nearDepthEdge(const cv::Mat& depth, const Eigen::Vector2d& uv, int radius) {
  float lo = 1e30f, hi = 0;
  for (int dv = -radius; dv <= radius; ++dv)
    for (int du = -radius; du <= radius; ++du) {
      const int x = std::clamp(static_cast<int>(uv.x()) + du, 0, depth.cols - 1);
      const int y = std::clamp(static_cast<int>(uv.y()) + dv, 0, depth.rows - 1);
      const float d = depth.at<float>(y, x);
      lo = std::min(lo, d);
      hi = std::max(hi, std::isfinite(d) ? d : 1e30f);
    }
  return hi - lo > 0.05f * lo;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2) throw std::runtime_error("usage: bench_track_accuracy SEQ_DIR [--frames N] [--no-anchors] [--vio klt|truth --out TRAJ.tum [--noise PX]]");
  const std::string dir = argv[1];
  int max_frames = 1 << 30;
  bool anchors = true;
  std::string vio_mode, out_path;
  double noise_px = 0.3;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--frames") max_frames = std::stoi(value());
    else if (a == "--no-anchors") anchors = false;
    else if (a == "--vio") vio_mode = value();
    else if (a == "--out") out_path = value();
    else if (a == "--noise") noise_px = std::stod(value());
    else throw std::runtime_error("unknown argument " + a);
  }
  if (!vio_mode.empty() && ((vio_mode != "klt" && vio_mode != "truth") || out_path.empty()))
    throw std::runtime_error("--vio takes klt or truth, and needs --out");

  const std::string info = dir + "/mav0/sim.yaml";
  if (simInfo(info, "mode") != "synthetic" || simInfo(info, "level") != "none")
    throw std::runtime_error(info + ": needs a synthetic sequence of level none (a static scene)");
  const std::string scene_name = simInfo(info, "scene");
  const std::string motion = simInfo(info, "motion", "glide");  // older sequences: glide
  const uint64_t seed = std::stoull(simInfo(info, "seed"));
  const int64_t start = std::stoll(simInfo(info, "start_ns")), end = std::stoll(simInfo(info, "end_ns"));
  const data::SineTrajectory path = data::makeSceneTrajectory(scene_name, seed, start, end, motion);
  const data::SimScene scene = data::buildStaticScene(scene_name, seed, path);
  data::SimRenderer renderer{data::SimCamera{}};

  data::EurocReader reader(dir);
  const data::CameraModel camera(reader.camera());
  const Eigen::Isometry3d T_B_C = reader.camera().T_B_C;
  vio::FeatureTrackerOptions tracker_options;
  tracker_options.anchor_alignment = anchors;
  vio::FeatureTracker tracker(tracker_options, camera);

  vio::ImuPreintegrationOptions imu;
  imu.gyro_noise_density = reader.imuNoise().gyro_noise_density;
  imu.accel_noise_density = reader.imuNoise().accel_noise_density;
  imu.gyro_random_walk = reader.imuNoise().gyro_random_walk;
  imu.accel_random_walk = reader.imuNoise().accel_random_walk;
  vio::SlidingWindowEstimator estimator(vio::EstimatorOptions{}, 0.5 * (camera.fx() + camera.fy()),
                                        T_B_C, imu);
  std::unique_ptr<data::TumTrajectoryWriter> writer;
  if (!vio_mode.empty()) writer = std::make_unique<data::TumTrajectoryWriter>(out_path);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise_px);

  std::map<int64_t, Eigen::Vector3d> point_W;                // feature id -> true point
  std::map<int64_t, bool> near_edge;                         // feature id -> started near an edge
  std::map<int64_t, std::vector<Eigen::Vector2d>> errors;    // feature id -> error per frame
  std::map<int, Percentiles> by_age;
  Percentiles change1, change10, change30, change30_edge, change30_plain;
  long reanchored = 0, tracked = 0;
  int frames = 0;
  data::Measurement m;
  data::SimFrame rendered;
  Eigen::Matrix3d R_W_C_previous = Eigen::Matrix3d::Identity();
  while (frames < max_frames && reader.next(m)) {
    if (m.isImu()) {
      if (writer) estimator.addImu(m.imu);
      continue;
    }
    const data::SimBodyState body = path.stateAt(m.frame.t_ns);
    const Eigen::Isometry3d T_W_C = Eigen::Translation3d(body.p_W_B) * body.q_W_B * T_B_C;
    if (frames > 0) tracker.setPredictedRotation(R_W_C_previous.transpose() * T_W_C.linear());
    R_W_C_previous = T_W_C.linear();
    const vio::FrameFeatures f = tracker.trackFrame(m.frame.t_ns, m.frame.image);
    reanchored += tracker.lastStats().reanchored;
    tracked += tracker.lastStats().tracked;
    renderer.render(scene, T_W_C, m.frame.t_ns, data::SimRenderOptions{}, &rendered);

    vio::FrameFeatures truth = f;  // the same tracks at their true positions (+ noise)
    truth.ids.clear(), truth.pixels.clear(), truth.prev_pixels.clear();
    truth.normalized.clear(), truth.track_counts.clear(), truth.velocities.clear();
    for (size_t k = 0; k < f.size(); ++k) {
      const Eigen::Vector2d uv(f.pixels[k].x, f.pixels[k].y);
      Eigen::Vector2d true_uv = uv;
      if (f.track_counts[k] == 1) {
        double z = 0;
        if (!depthAt(rendered.depth, uv, &z)) continue;
        point_W[f.ids[k]] = T_W_C * (camera.unproject(uv) * z);
        near_edge[f.ids[k]] = nearDepthEdge(rendered.depth, uv, 5);
      } else {
        const auto it = point_W.find(f.ids[k]);
        if (it == point_W.end() || !camera.project(T_W_C.inverse() * it->second, &true_uv)) continue;
        const Eigen::Vector2d e = uv - true_uv;
        by_age[std::min(f.track_counts[k], 40)].v.push_back(e.norm());
        auto& h = errors[f.ids[k]];
        h.push_back(e);
        const size_t n = h.size();
        if (n > 1) change1.v.push_back((h[n - 1] - h[n - 2]).norm());
        if (n > 10) change10.v.push_back((h[n - 1] - h[n - 11]).norm());
        if (n > 30) {
          const double c = (h[n - 1] - h[n - 31]).norm();
          change30.v.push_back(c);
          (near_edge[f.ids[k]] ? change30_edge : change30_plain).v.push_back(c);
        }
        true_uv += Eigen::Vector2d(gauss(rng), gauss(rng));
      }
      truth.ids.push_back(f.ids[k]);
      truth.pixels.emplace_back(static_cast<float>(true_uv.x()), static_cast<float>(true_uv.y()));
      truth.prev_pixels.push_back(f.prev_pixels[k]);
      truth.normalized.push_back(camera.pixelToNormalized(true_uv));
      truth.track_counts.push_back(f.track_counts[k]);
      truth.velocities.push_back(f.velocities[k]);
    }
    if (writer) {
      if (const auto state = estimator.addFrame(vio_mode == "truth" ? truth : f)) {
        data::StampedPose p;
        p.t_ns = state->t_ns, p.p_W_B = state->p_W_B, p.q_W_B = state->q_W_B;
        writer->write(p);
      }
    }
    if (++frames % 200 == 0) std::cerr << "bench_track_accuracy: frame " << frames << "\n";
  }
  std::printf("%s: %d frames, anchors %s, re-anchored %.1f %% of tracked steps\n", dir.c_str(), frames,
              anchors ? "on" : "off", 100.0 * reanchored / std::max(1L, tracked));
  for (auto& [age, p] : by_age) {
    if (age != 2 && age != 5 && age % 10 != 0) continue;
    const std::string label = "error at age " + std::to_string(age) + (age == 40 ? "+" : "");
    p.print(label.c_str());
  }
  change1.print("change over 1 frame");
  change10.print("change over 10 frames");
  change30.print("change over 30 frames");
  change30_plain.print("  ... away from depth edges");
  change30_edge.print("  ... within 5 px of a depth edge");
  if (writer) {
    writer->close();
    std::printf("trajectory (%s tracks): %s; estimator resets %d\n", vio_mode.c_str(), out_path.c_str(),
                estimator.stats().resets);
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "bench_track_accuracy: " << e.what() << "\n";
  return 2;
}

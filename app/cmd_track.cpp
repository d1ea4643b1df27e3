// `adugs track --detections det.txt --out DIR`: the enhanced SORT tracker alone, on a
// MOTChallenge detection file (the public detections trackers are benchmarked with), writing
// DIR/tracks.txt in MOTChallenge format for `adugs eval-mot`.
//
// Track output rule (MOT files): a track is written in a frame when a detection was fused into it
// in that frame and it has min_hits detections (or the sequence is younger than min_hits frames),
// as the original SORT does; --write-coasting also writes the predicted boxes of tracks that
// missed their detection (what the dynamic mask uses, but false positives for MOT scoring).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "data/input_error.h"
#include "data/mot_io.h"
#include "tracking/sort_tracker.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct TrackArgs {
  std::string detections, out_dir = "out/track";
  double min_score = -1e9;
  bool write_coasting = false;
  bool fixed_noise = false;
  tracking::SortOptions sort;
};

void runTrack(const TrackArgs& a) {
  const auto detections = data::readMotFile(a.detections);
  if (detections.empty()) throw data::InputError(a.detections, 0, "", "no detections in the file");
  tracking::SortOptions options = a.sort;
  if (a.fixed_noise) options.filter.lambda = 1e6;  // erf saturates at once: R = beta, a fixed R
  tracking::SortTracker tracker(options);
  fs::create_directories(a.out_dir);
  const std::string path = (fs::path(a.out_dir) / "tracks.txt").string();
  std::ofstream out(path);
  if (!out) throw data::InputError(path, 0, "", "cannot write");
  out << std::fixed << std::setprecision(2);
  const int last_frame = detections.rbegin()->first;
  size_t rows = 0;
  for (int frame = 1; frame <= last_frame; ++frame) {
    std::vector<tracking::Detection> dets;
    if (const auto it = detections.find(frame); it != detections.end())
      for (const data::MotBox& b : it->second)
        if (b.confidence >= a.min_score)
          dets.push_back({tracking::Box::fromCorners(b.left, b.top, b.left + b.width, b.top + b.height), 0,
                          b.confidence});
    for (const tracking::TrackedObject& t : tracker.update(dets)) {
      if (!t.detected && !a.write_coasting) continue;
      // MOTChallenge: 1-based top-left pixel coordinates.
      out << frame << "," << t.id << "," << t.box.left() + 1 << "," << t.box.top() + 1 << "," << t.box.w << ","
          << t.box.h << ",1,-1,-1,-1\n";
      ++rows;
    }
  }
  out.close();
  if (!out) throw data::InputError(path, 0, "", "write failed");
  std::cout << "adugs track: " << last_frame << " frames, " << rows << " track boxes -> " << path << "\n";
}

}  // namespace

void registerTrackCommand(CLI::App& root) {
  auto args = std::make_shared<TrackArgs>();
  args->sort.max_age = 1;
  args->sort.min_hits = 3;
  CLI::App* cmd = root.add_subcommand("track", "Run the enhanced SORT tracker on MOTChallenge detections");
  cmd->add_option("--detections", args->detections, "MOTChallenge det.txt (frame,-1,left,top,w,h,score,...)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out_dir, "output folder (tracks.txt)")->capture_default_str();
  cmd->add_option("--min-score", args->min_score, "ignore detections scoring below this");
  cmd->add_option("--max-age", args->sort.max_age, "frames a track survives without a detection")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--min-hits", args->sort.min_hits, "detections before a track is written")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--iou-min", args->sort.iou_min, "smallest IoU of an association")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--write-coasting", args->write_coasting,
                "also write predicted boxes of tracks without a detection in the frame");
  cmd->add_flag("--recovery", args->sort.observation_centric_recovery,
                "OC-SORT's observation-centric re-update when a coasting track is found again");
  tracking::AdaptiveNoiseOptions& r = args->sort.filter;
  cmd->add_option("--lambda", r.lambda, "adaptive R: R = beta * erf(lambda * innovation RMSE) [1/px]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--beta-pos", r.beta_pos, "adaptive R: largest R on cx, cy [px^2]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--beta-size", r.beta_size, "adaptive R: largest R on w, h [px^2]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--window", r.window, "adaptive R: innovations kept (N)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_flag("--fixed-noise", args->fixed_noise,
                "fixed measurement noise R = beta instead of the adaptive erf-shaped R (ablation)");
  cmd->callback([args] { runTrack(*args); });
}

}  // namespace adugs::app

// Speed of the dynamic-object stages that need no model files: SORT update (Hungarian + adaptive
// Kalman) with many objects, and box-prompted GrabCut segmentation of a simulated street frame.
#include <benchmark/benchmark.h>

#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>

#include "data/sim_sequence.h"
#include "tests/test_support.h"
#include "tracking/grabcut_segmenter.h"
#include "tracking/sort_tracker.h"

namespace adugs::tracking {
namespace {

// n objects moving at constant velocity, detected every frame with 2 px jitter.
void BM_SortUpdate(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::mt19937 rng(1);
  std::normal_distribution<double> jitter(0.0, 2.0);
  SortTracker sort;
  int frame = 0;
  for (auto _ : state) {
    std::vector<Detection> dets;
    for (int i = 0; i < n; ++i)
      dets.push_back({Box{40.0 * (i % 18) + 2.0 * frame + jitter(rng),
                          30.0 * (i / 18) + 40 + jitter(rng), 30, 60},
                      0});
    benchmark::DoNotOptimize(sort.update(dets));
    ++frame;
  }
}
BENCHMARK(BM_SortUpdate)->Arg(5)->Arg(20)->Arg(50)->Unit(benchmark::kMicrosecond);

// GrabCut on every object box (visible > 20 %) of a 752x480 street/high frame.
void BM_GrabCutStreetFrame(benchmark::State& state) {
  test::TempDir tmp("adugs_bench_seg");
  data::SimSequenceOptions o;
  o.scene = "street";
  o.level = data::SimLevel::kHigh;
  o.seed = 3;
  o.duration_s = 1.0;
  o.progress = false;
  data::generateSimSequence(o, tmp.path().string());
  // Boxes of the last frame from the MOT file.
  std::ifstream gt((tmp / "mav0/objects0/gt.txt").string());
  std::string line;
  std::map<int, std::vector<Box>> boxes;
  while (std::getline(gt, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    int frame, id, cls;
    double l, t, w, h, conf, vis;
    if (s >> frame >> id >> l >> t >> w >> h >> conf >> cls >> vis && vis > 0.2)
      boxes[frame].push_back(Box{l - 1 + w / 2, t - 1 + h / 2, w, h});
  }
  std::ifstream csv((tmp / "mav0/cam0/data.csv").string());
  std::vector<std::string> names;
  std::getline(csv, line);
  while (std::getline(csv, line)) names.push_back(line.substr(line.find(',') + 1));
  const int f = static_cast<int>(names.size());
  const cv::Mat image =
      cv::imread((tmp / ("mav0/cam0/data/" + names.back())).string(), cv::IMREAD_GRAYSCALE);
  GrabCutSegmenter seg;
  for (auto _ : state) benchmark::DoNotOptimize(seg.segment(image, boxes[f]));
  state.counters["boxes"] = static_cast<double>(boxes[f].size());
}
BENCHMARK(BM_GrabCutStreetFrame)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace adugs::tracking

BENCHMARK_MAIN();

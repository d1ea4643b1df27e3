// Speed of the dynamic-object stages that need no model files: SORT update (Hungarian + adaptive
// Kalman) with many objects, and box-prompted GrabCut segmentation of a simulated street frame.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <random>

#include "tests/test_support.h"
#include "tests/tracking/simulated_street.h"
#include "tracking/segment/grabcut_segmenter.h"
#include "tracking/sort/sort_tracker.h"

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
  const auto street = test_support::makeSimulatedStreet(tmp.path(), 1.0);
  const int f = static_cast<int>(street.image_names.size());
  const cv::Mat image = cv::imread(street.imagePath(f), cv::IMREAD_GRAYSCALE);
  const std::vector<Box> boxes = street.visibleBoxes(f, 0.2);
  GrabCutSegmenter seg;
  for (auto _ : state) benchmark::DoNotOptimize(seg.segment(image, boxes));
  state.counters["boxes"] = static_cast<double>(boxes.size());
}
BENCHMARK(BM_GrabCutStreetFrame)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace adugs::tracking

BENCHMARK_MAIN();

// Render speed of the simulator: full-size 752x480 EuRoC-lens frames of the built-in scenes at the
// high dynamic level, one core. items_per_second = rendered frames per second (image + mask +
// boxes; no PNG encoding). The figure goes to doc/simulator.md.
#include <benchmark/benchmark.h>

#include "data/sim/sim_renderer.h"
#include "data/types.h"

namespace {

using namespace adugs::data;

void renderScene(benchmark::State& state, const std::string& name) {
  const int64_t t0 = 0, duration = secToNs(60);
  const SineTrajectory traj = makeSceneTrajectory(name, 3, t0, t0 + duration);
  SimScene scene = buildStaticScene(name, 3, traj);
  addDynamicObjects(scene, SimLevel::kHigh, 3, traj, defaultSimT_B_C());
  SimRenderer renderer{SimCamera()};
  SimRenderOptions options;
  options.noise_sigma = 1.0;
  SimFrame frame;
  int64_t t = t0;
  for (auto _ : state) {
    const SimBodyState s = traj.stateAt(t);
    Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
    T_W_B.linear() = s.q_W_B.toRotationMatrix();
    T_W_B.translation() = s.p_W_B;
    renderer.render(scene, T_W_B * defaultSimT_B_C(), t, options, &frame);
    benchmark::DoNotOptimize(frame.image.data);
    t += secToNs(0.05);  // walk along the 20 Hz sequence
    if (t > duration) t = t0;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_SimRenderRoomHigh(benchmark::State& state) { renderScene(state, "room"); }
void BM_SimRenderStreetHigh(benchmark::State& state) { renderScene(state, "street"); }

BENCHMARK(BM_SimRenderRoomHigh)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_SimRenderStreetHigh)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();

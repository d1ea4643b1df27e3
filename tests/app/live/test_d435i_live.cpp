// `adugs live --d435i` and `adugs record --d435i` end to end on the simulated camera (a sysfs tree,
// FIFOs as IIO device files, the fake V4L2 layer, a device thread in real time): the command's own
// code (openLiveSource with --d435i, then runPipeline / recordToAsl) runs in a child process of
// the test, so that it is stopped by a real SIGINT or by the camera going away, and its outputs
// are read back as a user would. Only the system calls differ from `adugs live --d435i` (the fake
// kernel layer lives in the test, not in the adugs binary); the command line's own wiring is
// checked with the binary against the same tree, where the real ioctls fail on the fake nodes.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>

#include "app/asl_recorder.h"
#include "app/live_sources.h"
#include "app/run_pipeline.h"
#include "app/source_lost.h"
#include "tests/data/live/fake_d435i.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace {
namespace fs = std::filesystem;

const std::string kD435iConfig = std::string(ADUGS_SOURCE_DIR) + "/data/config/d435i.yaml";

// data/config/d435i.yaml with its d435i: map pointed at the simulated camera's tree.
std::string configForFakeTree(const fs::path& dir, const fs::path& device_root) {
  std::string text = readFile(kD435iConfig);
  const size_t at = text.find("\nd435i:\n");
  EXPECT_NE(at, std::string::npos);
  text.insert(at + 8, "  sys_root: " + (device_root / "sys").string() + "\n  dev_root: " + (device_root / "dev").string() + "\n");
  const fs::path path = dir / "d435i_fake.yaml";
  std::ofstream(path) << text;
  return path.string();
}

struct ChildRun {
  double unplug_camera_after_s = 0;  // > 0: the camera goes away this long after it started
  double duration_s = 0;             // --duration
  bool record = false;               // adugs record --d435i instead of adugs live --d435i
};

// In the child: the simulated camera, then what `adugs live|record --d435i --config CONFIG --out
// OUT` does with it.
int runD435iCommand(const fs::path& device_root, const std::string& config, const fs::path& out, const ChildRun& run) {
  FakeD435iConfig device;
  device.still_textured_scene = true;
  FakeD435i fake(device_root, device);
  app::LiveSourceArgs args;
  args.d435i = true;
  args.sequence.duration_s = run.duration_s;
  data::OpenedSequence sequence = app::openLiveSource(args, config, out.string(), fake.v4l2());
  fake.start();
  std::thread unplug;
  if (run.unplug_camera_after_s > 0)
    unplug = std::thread([&] {
      std::this_thread::sleep_for(std::chrono::duration<double>(run.unplug_camera_after_s));
      fake.unplugCamera();
    });
  int exit_code = 0;
  try {
    if (run.record) {
      app::AslRecordOptions o;
      o.out_dir = out.string();
      app::recordToAsl(sequence, o);
    } else {
      app::PipelineRunArgs p;
      p.command = "live";
      p.out_dir = out.string();
      p.config_path = config;
      app::runPipeline(sequence, p);
    }
  } catch (const app::SourceLost& e) {  // as main() turns it into the exit code
    std::cerr << "adugs: " << e.what() << "\n";
    exit_code = app::kExitSourceLost;
  }
  if (unplug.joinable()) unplug.join();
  sequence.source.reset();  // the camera's controls put back before the device goes
  fake.stop();
  return exit_code;
}

// Poses in a TUM trajectory (lines that are not comments).
size_t poses(const fs::path& trajectory) {
  std::ifstream in(trajectory);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

// Waits until the trajectory being written holds `n` poses.
bool waitForPoses(const fs::path& trajectory, size_t n, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until) {
    if (poses(trajectory) >= n) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

TEST(D435iLive, RunsThePipelineOnTheCameraAndStopsCleanlyOnSigint) {
  TempDir dir("adugs_d435i_live");
  const std::string config = configForFakeTree(dir.path(), dir / "device");
  const fs::path out = dir / "out", log = dir / "live.log";
  AdugsProcess child([&] { return runD435iCommand(dir / "device", config, out, {}); }, log);
  // The camera at rest: static initialisation after its 1 s window, then a pose per frame.
  ASSERT_TRUE(waitForPoses(out / "trajectory.tum", 5, 30)) << readFile(log);
  child.signal(SIGINT);
  ASSERT_EQ(child.wait(std::chrono::seconds(30)), 0) << readFile(log);
  const fs::path summary = out / "summary.yaml";
  EXPECT_EQ(summaryText(summary, "command"), "live");
  EXPECT_EQ(summaryText(summary, "end"), "stopped");
  EXPECT_EQ(summaryText(summary, "end_detail"), "\"SIGINT\"");
  EXPECT_NE(summaryText(summary, "source").find("RealSense"), std::string::npos) << readFile(summary);
  EXPECT_EQ(summaryText(summary, "init_kind"), "static");
  const double frames = summaryNumber(summary, "frames_acquired");
  EXPECT_GE(frames, 20);  // the static window is 1 s at 30 Hz
  // 400 Hz united IMU, every sample acquired to the estimator (or after the last frame).
  const double imu = summaryNumber(summary, "imu_samples");
  EXPECT_GE(imu, 12 * frames);
  EXPECT_EQ(summaryNumber(summary, "imu_samples_to_estimator") + summaryNumber(summary, "imu_samples_after_last_frame"),
            imu);
  // Every pose estimated is in the trajectory: the frames inside were finished and flushed.
  EXPECT_GE(poses(out / "trajectory.tum"), 5u);
  EXPECT_EQ(static_cast<double>(poses(out / "trajectory.tum")), summaryNumber(summary, "poses"));
  EXPECT_NE(readFile(log).find("live: stopped (SIGINT)"), std::string::npos) << readFile(log);
}

TEST(D435iLive, ACameraUnpluggedMidRunEndsTheRunWithItsOutputsSaysWhyAndExitsWith4) {
  TempDir dir("adugs_d435i_live");
  const std::string config = configForFakeTree(dir.path(), dir / "device");
  const fs::path out = dir / "out", log = dir / "live.log";
  ChildRun run;
  run.unplug_camera_after_s = 3;
  AdugsProcess child([&] { return runD435iCommand(dir / "device", config, out, run); }, log);
  ASSERT_EQ(child.wait(std::chrono::seconds(40)), app::kExitSourceLost) << readFile(log);
  const fs::path summary = out / "summary.yaml";
  EXPECT_EQ(summaryText(summary, "end"), "end_of_source") << readFile(summary);
  EXPECT_NE(summaryText(summary, "end_detail").find("unplugged"), std::string::npos) << readFile(summary);
  EXPECT_GE(summaryNumber(summary, "frames_acquired"), 30);
  EXPECT_NE(readFile(log).find("live: the source ended ("), std::string::npos) << readFile(log);
  EXPECT_NE(readFile(log).find("adugs: the live source ended by itself: "), std::string::npos) << readFile(log);
  EXPECT_EQ(static_cast<double>(poses(out / "trajectory.tum")), summaryNumber(summary, "poses"));
}

// adugs record --d435i until the camera goes away; adugs run reads the folder back.
TEST(D435iLive, RecordWritesAnAslFolderThatAdugsRunReadsBack) {
  TempDir dir("adugs_d435i_record");
  const std::string config = configForFakeTree(dir.path(), dir / "device");
  const fs::path rec = dir / "rec", log = dir / "record.log";
  ChildRun run;
  run.record = true;
  run.unplug_camera_after_s = 2.5;
  AdugsProcess child([&] { return runD435iCommand(dir / "device", config, rec, run); }, log);
  // Everything acquired is written, and the exit code says the camera went away.
  ASSERT_EQ(child.wait(std::chrono::seconds(40)), app::kExitSourceLost) << readFile(log);
  const fs::path record = rec / "record.yaml";
  EXPECT_EQ(summaryText(record, "complete"), "true") << readFile(record);
  EXPECT_NE(summaryText(record, "end_detail").find("unplugged"), std::string::npos) << readFile(record);
  const double frames = summaryNumber(record, "frames_written");
  const double imu = summaryNumber(record, "imu_samples_written");
  EXPECT_GE(frames, 40);      // ~2 s at 30 Hz after the clock's warm-up
  EXPECT_GE(imu, 12 * frames);  // 400 Hz united samples: ~13 per frame
  EXPECT_EQ(csvRows(rec / "mav0/cam0/data.csv"), static_cast<size_t>(frames));
  EXPECT_EQ(csvRows(rec / "mav0/imu0/data.csv"), static_cast<size_t>(imu));
  EXPECT_NE(readFile(rec / "mav0/cam0/sensor.yaml").find("848"), std::string::npos);

  std::string run_log;
  ASSERT_EQ(runAdugs("run -q " + rec.string() + " --config " + kD435iConfig + " --out " + (dir / "run").string(), &run_log),
            0)
      << run_log;
  const fs::path run_summary = dir / "run/summary.yaml";
  EXPECT_EQ(summaryNumber(run_summary, "frames"), frames) << readFile(run_summary);
  // At rest with 1 g in SI units on the recorded IMU: the static initialisation, then poses.
  EXPECT_EQ(summaryText(run_summary, "init_kind"), "static") << readFile(run_summary);
  EXPECT_GT(summaryNumber(run_summary, "poses"), 0);
}

// The command line: --d435i reaches the D435i source with the config's d435i: map (the binary's
// real ioctls cannot open the simulated nodes: a clear error naming one, exit code 2), and
// exactly one source is accepted.
TEST(D435iLive, TheCommandLineOpensTheCameraTheConfigNames) {
  TempDir dir("adugs_d435i_cli");
  const fs::path device_root = dir / "device";
  FakeD435i fake(device_root);
  const std::string config = configForFakeTree(dir.path(), device_root);
  std::string log;
  EXPECT_EQ(runAdugs("live --d435i --config " + config + " --no-window --out " + (dir / "out").string(), &log), 2) << log;
  EXPECT_NE(log.find(fake.devRoot()), std::string::npos) << log;
  EXPECT_EQ(runAdugs("record --d435i --config " + config + " --out " + (dir / "rec").string(), &log), 2) << log;
  EXPECT_NE(log.find(fake.devRoot()), std::string::npos) << log;
  EXPECT_EQ(runAdugs("live --d435i --v4l2 /dev/video0 --out " + (dir / "out").string(), &log), 2) << log;
  EXPECT_NE(log.find("one source only"), std::string::npos) << log;
}

}  // namespace
}  // namespace adugs::test

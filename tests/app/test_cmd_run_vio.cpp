// `adugs run` with the visual-inertial estimator (the default) end to end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "app/run_config.h"
#include "data/formats/csv_reader.h"
#include "data/formats/imu_csv.h"
#include "data/formats/trajectory_io.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace {

using test::kSourceDir;

// The number right after `key` in a summary; NaN when the key is missing.
double yamlNumberAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  return at == std::string::npos ? std::nan("") : std::stod(text.substr(at + key.size()));
}

// The real EuRoC micro sequence stands still: static initialisation, and the issue's bar of
// less than 5 cm drift from the first pose over the 4.7 s.
TEST(CmdRunVio, RealEurocMicroInitialisesStaticallyAndStaysPut) {
  const auto seq = sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(seq);
  TempDir out;
  std::string log;
  const std::string gt = (seq / "groundtruth" / "V1_01_easy_vicon2gt.csv").string();
  ASSERT_EQ(runAdugs("run -q " + seq.string() + " --config " + kSourceDir +
                         "/data/config/euroc.yaml --gt " + gt + " --out " + out.path().string(),
                     &log),
            0)
      << log;
  const std::string summary = readFile(out / "summary.yaml");
  EXPECT_NE(summary.find("init_kind: static"), std::string::npos) << summary;
  EXPECT_NE(summary.find("resets: 0"), std::string::npos) << summary;
  const auto traj = data::readTrajectory((out / "trajectory.tum").string());
  ASSERT_GT(traj.size(), 70u);
  double max_drift = 0;
  for (const auto& p : traj) max_drift = std::max(max_drift, (p.p_W_B - traj.front().p_W_B).norm());
  std::cout << "micro: " << traj.size() << " poses, max drift from the first pose " << max_drift
            << " m\n";
  EXPECT_LT(max_drift, 0.05);
  EXPECT_TRUE(std::filesystem::exists(out / "eval.png"));
}

class CmdRunVioSim : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("adugs_run_vio_sim");
    std::string log;
    ASSERT_EQ(runAdugs("sim --scene street --level high --seed 5 --duration 6 --out " +
                           dir_->path().string(),
                       &log),
              0)
        << log;
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
};
TempDir* CmdRunVioSim::dir_ = nullptr;

// `adugs sim --accel-bias` starts the accelerometer's bias there: every accelerometer sample is
// the unbiased sequence's plus that bias (same seed: the same noise and the same random walk), the
// ground truth's bias starts at it and sim.yaml records it. A hybrid sequence refuses it.
TEST(CmdSim, AccelBiasShiftsEveryAccelerometerSample) {
  TempDir dir("adugs_sim_bias");
  std::string log;
  const std::string base = "sim --scene room --level none --seed 3 --duration 2 --out ";
  ASSERT_EQ(runAdugs(base + (dir / "plain").string(), &log), 0) << log;
  ASSERT_EQ(runAdugs(base + (dir / "biased").string() + " --accel-bias 0.1,-0.05,0.08", &log), 0) << log;
  const auto plain = data::readEurocImuCsv((dir / "plain/mav0/imu0/data.csv").string());
  const auto biased = data::readEurocImuCsv((dir / "biased/mav0/imu0/data.csv").string());
  ASSERT_EQ(plain.size(), biased.size());
  ASSERT_GT(plain.size(), 300u);
  const Eigen::Vector3d bias(0.1, -0.05, 0.08);
  for (size_t i = 0; i < plain.size(); ++i)
    ASSERT_LT((biased[i].accel - plain[i].accel - bias).norm(), 1e-9) << "sample " << i;
  data::CsvReader gt((dir / "biased/mav0/state_groundtruth_estimate0/data.csv").string());
  ASSERT_TRUE(gt.next());
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(gt.doubleAt(14 + a), bias[a], 1e-9);  // b_a_RS_S columns
  EXPECT_NE(readFile(dir / "biased/mav0/sim.yaml").find("initial_accel_bias: [0.1, -0.05, 0.08]"), std::string::npos)
      << readFile(dir / "biased/mav0/sim.yaml");

  EXPECT_EQ(runAdugs("sim --trajectory gt.csv --imu imu.csv --calib sensor.yaml --accel-bias 0.1,0,0 --out " +
                         (dir / "hybrid").string(),
                     &log),
            2)
      << log;
  EXPECT_NE(log.find("--accel-bias"), std::string::npos) << log;
  for (const char* bad : {"nan,0,0", "0,20,0"}) {
    EXPECT_EQ(runAdugs(base + (dir / "bad").string() + " --accel-bias " + bad, &log), 2) << bad << "\n" << log;
    EXPECT_NE(log.find("within +-10 m/s^2"), std::string::npos) << log;
  }
  EXPECT_NE(runAdugs(base + (dir / "bad").string() + " --accel-bias a,0,0", &log), 0) << log;
}

// On a gentle street path (seed 33, nothing moving) the IMU accelerates little: with the
// accelerometer bias free after the visual-inertial initialisation, the window moved it to
// 0.18 m/s^2 (true: < 0.01) with the scale 30 % short, and the marginalisation prior kept both
// (ATE 0.61 m over 26 m). sim.yaml holds the bias near zero at the initialisation (0.10 m).
TEST(CmdRunVioBiasPrior, InitialisationBiasPriorKeepsTheScaleOnAGentlePath) {
  TempDir dir("adugs_run_bias_prior");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene street --level none --seed 33 --duration 20 --out " + (dir / "seq").string(), &log), 0)
      << log;
  const std::string sim_yaml = readFile(std::filesystem::path(kSourceDir) / "data/config/sim.yaml");
  const std::string key = "vi_init_accel_bias_sigma: 0.05";
  ASSERT_NE(sim_yaml.find(key), std::string::npos) << "sim.yaml no longer sets " << key;
  std::string free_yaml = sim_yaml;
  free_yaml.replace(free_yaml.find(key), key.size(), "vi_init_accel_bias_sigma: 0");
  writeText(dir / "free.yaml", free_yaml);
  for (const char* config : {"held", "free"}) {
    const std::string path = std::string(config) == "held" ? std::string(kSourceDir) + "/data/config/sim.yaml"
                                                            : (dir / "free.yaml").string();
    ASSERT_EQ(runAdugs("run -q " + (dir / "seq").string() + " --config " + path + " --out " + (dir / config).string(),
                       &log),
              0)
        << log;
  }
  const double held = summaryNumber(dir / "held/summary.yaml", "ate_se3_rmse_m");
  const double free = summaryNumber(dir / "free/summary.yaml", "ate_se3_rmse_m");
  EXPECT_LT(held, 0.2) << "measured 0.10 m";
  EXPECT_GT(free, 2 * held) << "measured 0.61 m: if the free bias no longer runs away here, the prior's case is gone";
}

TEST_F(CmdRunVioSim, GroundTruthMasksRunEndToEndWithSummary) {
  TempDir out;
  std::string log;
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --config " + kSourceDir +
                         "/data/config/sim.yaml --mask gt --out " + out.path().string(),
                     &log),
            0)
      << log;
  const std::string summary = readFile(out / "summary.yaml");
  for (const char* key : {"mask: gt", "keyframes:", "init_kind: visual-inertial",
                          "frontend_median:", "backend_median:", "ate_se3_rmse_m:"})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  const auto traj = data::readTrajectory((out / "trajectory.tum").string());
  EXPECT_GT(traj.size(), 90u);
  EXPECT_NE(log.find("ATE (se3)"), std::string::npos) << log;
  // The settled ATE is `adugs eval --skip-first 3` of the same two files.
  std::string eval_log;
  ASSERT_EQ(runAdugs("eval --est " + (out / "trajectory.tum").string() + " --gt " +
                         (dir_->path() / "mav0/state_groundtruth_estimate0/data.csv").string() + " --skip-first 3",
                     &eval_log),
            0)
      << eval_log;
  std::smatch printed;
  ASSERT_TRUE(std::regex_search(eval_log, printed, std::regex(R"(trans \[m\]\s+([0-9.]+))"))) << eval_log;
  const double settled = summaryNumber(out / "summary.yaml", "ate_se3_rmse_settled_m");
  EXPECT_GT(settled, 0.0) << summary;
  EXPECT_NEAR(settled, std::stod(printed[1]), 2e-6) << eval_log;
  // The shape and the scale apart are `adugs eval --align sim3` of the same two files; with the
  // scale free the error cannot be larger.
  ASSERT_EQ(runAdugs("eval --est " + (out / "trajectory.tum").string() + " --gt " +
                         (dir_->path() / "mav0/state_groundtruth_estimate0/data.csv").string() + " --align sim3",
                     &eval_log),
            0)
      << eval_log;
  std::smatch sim3_ate, length_error_text;
  ASSERT_TRUE(std::regex_search(eval_log, sim3_ate, std::regex(R"(trans \[m\]\s+([0-9.]+))"))) << eval_log;
  ASSERT_TRUE(std::regex_search(eval_log, length_error_text, std::regex(R"(the estimate is ([0-9.]+) % (short|long))"))) << eval_log;
  const double shape = summaryNumber(out / "summary.yaml", "ate_sim3_rmse_m");
  EXPECT_NEAR(shape, std::stod(sim3_ate[1]), 2e-6) << eval_log;
  EXPECT_LE(shape, summaryNumber(out / "summary.yaml", "ate_se3_rmse_m")) << summary;
  const double length_error = std::stod(length_error_text[1]) * (length_error_text[2] == "short" ? -1 : 1);
  EXPECT_NEAR(summaryNumber(out / "summary.yaml", "scale_error_percent"), length_error, 1e-3) << eval_log;
  EXPECT_NE(log.find("ATE (sim3)"), std::string::npos) << log;
  // The initialisation's scale uncertainty is reported, and sim.yaml's check accepted it.
  const double scale_std = summaryNumber(out / "summary.yaml", "init_scale_relative_std");
  const double cut = app::loadRunConfig(kSourceDir + std::string("/data/config/sim.yaml")).estimator.init.max_scale_relative_std;
  ASSERT_GT(cut, 0.0) << "sim.yaml no longer sets init: max_scale_relative_std";
  EXPECT_GT(scale_std, 0.0) << summary;
  EXPECT_LE(scale_std, cut) << summary;
}

// The class-free motion cue alone prompts the masks (no model): in the room the people and boxes
// walk across the camera's view, and most of their pixels are masked, most masked pixels theirs
// (60 s of this sequence: recall 0.80, precision 0.67, doc/tracking.md).
TEST(CmdRunVioMotionCue, MasksTheMoversOfTheRoomWithoutAModel) {
  TempDir seq("adugs_run_motion");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene room --level high --seed 6 --duration 6 --out " + seq.path().string(), &log), 0) << log;
  TempDir out;
  ASSERT_EQ(runAdugs("run -q " + seq.path().string() + " --config " + kSourceDir + "/data/config/sim.yaml --mask motion --out " +
                         out.path().string(),
                     &log),
            0)
      << log;
  const std::string summary = readFile(out / "summary.yaml");
  EXPECT_NE(summary.find("mask: motion"), std::string::npos) << summary;
  EXPECT_NE(summary.find("motion_cue: true"), std::string::npos) << summary;
  const double recall = yamlNumberAfter(summary, "dynamic_mask_vs_exact: {recall: ");
  const double precision = yamlNumberAfter(summary, ", precision: ");
  EXPECT_GE(recall, 0.5) << summary;     // 0.75 measured
  EXPECT_GE(precision, 0.4) << summary;  // 0.54 measured
  // Per mover class, from the simulator's boxes (objects0/gt.txt): the room's movers are people.
  const double people = yamlNumberAfter(summary, "dynamic_mask_recall_per_class: {person: ");
  EXPECT_GE(people, 0.4) << summary;
  EXPECT_LE(people, 1.0) << summary;
  EXPECT_GT(data::readTrajectory((out / "trajectory.tum").string()).size(), 30u);  // initialised after ~3 s
  EXPECT_GT(summaryNumber(out / "summary.yaml", "masked_image_fraction"), 0.0);

  // The cue's options come from the run config's dynamic: map (motion_cue:): asking for 1000
  // moving points per object leaves nothing to mask.
  TempDir strict;
  writeText(strict / "cfg.yaml", readFile(kSourceDir + std::string("/data/config/sim.yaml")) +
                                      "dynamic:\n  motion_cue:\n    min_points: 1000\n");
  ASSERT_EQ(runAdugs("run -q " + seq.path().string() + " --config " + (strict / "cfg.yaml").string() +
                         " --mask motion --duration 3 --out " + (strict / "run").string(),
                     &log),
            0)
      << log;
  EXPECT_EQ(summaryNumber(strict / "run/summary.yaml", "masked_image_fraction"), 0.0);
}

// Where nothing moves, every mask is a false box of the cue, and a few static features dropped can
// cost the estimator (doc/results.md, "Fewer false boxes"). A box needs four moving points by
// default: on this room, 10 s at level none, the false mask is 0.15 % of the image against 0.24 %
// with three points (0.17 / 0.36 % before the still points' tracking of 2026-12-07, which lost
// fewer of them and made fewer false movers at either count; seeds 7 and 10 then: 0.66 / 1.64 %
// and 0.22 / 0.44 %).
TEST(CmdRunVioMotionCue, FourMovingPointsMakeABoxSoAStaticRoomIsBarelyMasked) {
  TempDir seq("adugs_run_motion_static");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene room --level none --seed 5 --duration 10 --out " + seq.path().string(), &log), 0) << log;
  const std::string sim_config = readFile(kSourceDir + std::string("/data/config/sim.yaml"));
  TempDir out;
  // Without the corners' test (next test), which leaves this room no false box at all.
  writeText(out / "default.yaml", sim_config + "dynamic:\n  motion_cue:\n    min_corner_points: 0\n");
  writeText(out / "three.yaml", sim_config + "dynamic:\n  motion_cue:\n    min_corner_points: 0\n    min_points: 3\n");
  for (const char* config : {"default", "three"}) {
    ASSERT_EQ(runAdugs("run -q " + seq.path().string() + " --config " + (out / (std::string(config) + ".yaml")).string() +
                           " --mask motion --out " + (out / config).string(),
                       &log),
              0)
        << log;
  }
  const double four_points = summaryNumber(out / "default/summary.yaml", "masked_image_fraction");
  const double three_points = summaryNumber(out / "three/summary.yaml", "masked_image_fraction");
  EXPECT_GT(three_points, 0.0);  // the cue did run and found its usual false boxes
  EXPECT_LE(four_points, 0.75 * three_points) << four_points << " against " << three_points;
  EXPECT_LT(four_points, 0.0025);
}

// The false boxes of a static scene are points on straight edges, which slide along them: a box
// needs two corners among its moving points by default (min_corner_points), and this street, 10 s
// at level none, is then not masked at all - the run is the unmasked one (1.3 % of the image
// without the test; doc/results.md, "Two corners make a box").
TEST(CmdRunVioMotionCue, TwoCornersMakeABoxSoAStaticStreetIsNotMasked) {
  TempDir seq("adugs_run_motion_street");
  std::string log;
  ASSERT_EQ(runAdugs("sim --scene street --level none --seed 9 --duration 10 --out " + seq.path().string(), &log), 0) << log;
  const std::string sim_config = readFile(kSourceDir + std::string("/data/config/sim.yaml"));
  TempDir out;
  writeText(out / "edges.yaml", sim_config + "dynamic:\n  motion_cue:\n    min_corner_points: 0\n");
  const std::string sim_yaml = kSourceDir + std::string("/data/config/sim.yaml");
  for (const auto& [name, args] : std::vector<std::pair<std::string, std::string>>{
           {"corners", "--config " + sim_yaml + " --mask motion"},
           {"edges", "--config " + (out / "edges.yaml").string() + " --mask motion"},
           {"unmasked", "--config " + sim_yaml + " --mask none"}})
    ASSERT_EQ(runAdugs("run -q " + seq.path().string() + " " + args + " --out " + (out / name).string(), &log), 0) << log;
  EXPECT_GT(summaryNumber(out / "edges/summary.yaml", "masked_image_fraction"), 0.0);  // the edges' false boxes
  EXPECT_EQ(summaryNumber(out / "corners/summary.yaml", "masked_image_fraction"), 0.0);
  EXPECT_EQ(readFile((out / "corners/trajectory.tum").string()), readFile((out / "unmasked/trajectory.tum").string()));
}

// Real images of a static room (EuRoC V1_01, 4.7 s, the platform still): nothing moves, so the cue
// should mask next to nothing. Before the estimator's first state the gyro's bias is unknown, and
// V1_01's 0.077 rad/s about the optical axis turned the image's edges by over a pixel per frame:
// the cue boxed the left edge on the first 22 frames, 2.2 % of the image over the run. With the
// turn found from the points (MotionCue::fitRoll) 0.1 % are left, four frames on the mattress.
TEST(CmdRunVioMotionCue, ARealStaticRoomIsBarelyMaskedBeforeTheGyroBiasIsKnown) {
  const auto seq = sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(seq);
  TempDir out;
  std::string log;
  ASSERT_EQ(runAdugs("run -q " + seq.string() + " --mask motion --out " + out.path().string(), &log), 0) << log;
  EXPECT_LT(summaryNumber(out / "summary.yaml", "masked_image_fraction"), 0.005);
}

TEST_F(CmdRunVioSim, MaskOfTheWrongSizeIsAnErrorNamingTheFile) {
  TempDir copy;
  std::filesystem::copy(dir_->path(), copy.path(), std::filesystem::copy_options::recursive);
  const auto masks = copy.path() / "mav0" / "mask0" / "data";
  const auto first = *std::filesystem::directory_iterator(masks);
  cv::imwrite(first.path().string(), cv::Mat::zeros(10, 10, CV_8UC1));
  TempDir out;
  std::string log;
  EXPECT_EQ(
      runAdugs("run -q " + copy.path().string() + " --mask gt --out " + out.path().string(), &log),
      2)
      << log;
  EXPECT_NE(log.find(first.path().filename().string()), std::string::npos) << log;
  EXPECT_NE(log.find("10x10"), std::string::npos) << log;
}

TEST_F(CmdRunVioSim, DetectorMasksRunTheWholeDynamicObjectStage) {
  const auto model = sharedModelsDir() / "yolox_nano" / "yolox_nano.onnx";
  ADUGS_REQUIRE_SHARED(model);
  TempDir out;
  std::string log;
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() +
                         " --mask detector --segmenter box --detector-model " + model.string() +
                         " --out " + out.path().string(),
                     &log),
            0)
      << log;
  const std::string summary = readFile(out / "summary.yaml");
  EXPECT_NE(summary.find("mask: detector"), std::string::npos) << summary;
  EXPECT_NE(summary.find("dynamic_mask_median:"), std::string::npos) << summary;
  EXPECT_NE(summary.find("masked_image_fraction:"), std::string::npos) << summary;
  // The simulator's exact masks score the detector's: recall and precision of the dynamic pixels.
  EXPECT_NE(summary.find("dynamic_mask_vs_exact: {recall: "), std::string::npos) << summary;
  EXPECT_EQ(summary.find("dynamic_mask_vs_exact_per_cue"), std::string::npos) << "one cue only:\n" << summary;
  // With the motion cue beside the detector, each cue's share of the one mask is scored: the
  // mask inside its boxes, so neither recall can exceed the whole mask's.
  TempDir both;
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask detector --motion-cue --segmenter box --detector-model " +
                         model.string() + " --duration 3 --out " + both.path().string(),
                     &log),
            0)
      << log;
  const std::string per_cue = readFile(both / "summary.yaml");
  const double recall = yamlNumberAfter(per_cue, "dynamic_mask_vs_exact: {recall: ");
  const size_t at = per_cue.find("dynamic_mask_vs_exact_per_cue: {detector: {recall: ");
  ASSERT_NE(at, std::string::npos) << per_cue;
  const std::string cues = per_cue.substr(at);
  const double detector_recall = yamlNumberAfter(cues, "{detector: {recall: ");
  const double motion_recall = yamlNumberAfter(cues, "motion: {recall: ");
  EXPECT_GT(motion_recall, 0.0) << cues;  // the street's movers move against the camera's motion
  for (const double r : {detector_recall, motion_recall}) {
    EXPECT_GE(r, 0.0) << cues;
    EXPECT_LE(r, recall + 1e-9) << cues;
  }
  // Without a model the detector mask is refused with a message naming the option.
  EXPECT_NE(
      runAdugs("run -q " + dir_->path().string() + " --mask detector --out " + out.path().string(),
               &log),
      0);
  EXPECT_NE(log.find("detector-model"), std::string::npos) << log;
}

// --overlay: one video frame per camera frame, the mask tinted red where the simulator's people are.
TEST_F(CmdRunVioSim, OverlayVideoShowsTheMaskAndFeatures) {
  TempDir out;
  std::string log;
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask gt --overlay " + (out / "overlay.avi").string() +
                         " --out " + out.path().string(),
                     &log),
            0)
      << log;
  cv::VideoCapture video((out / "overlay.avi").string());
  ASSERT_TRUE(video.isOpened());
  const int frames = static_cast<int>(video.get(cv::CAP_PROP_FRAME_COUNT));
  int images = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir_->path() / "mav0" / "cam0" / "data")) images += e.is_regular_file();
  EXPECT_EQ(frames, images);
  // Somewhere the tint: red well above green and blue (MJPG blurs it a little).
  cv::Mat frame;
  int reddish = 0;
  while (video.read(frame)) {
    std::vector<cv::Mat> bgr;
    cv::split(frame, bgr);
    cv::Mat red_dominant = (bgr[2] > bgr[1] + 40) & (bgr[2] > bgr[0] + 40);
    reddish += cv::countNonZero(red_dominant);
  }
  EXPECT_GT(reddish, 1000);
  EXPECT_EQ(runAdugs("run -q " + dir_->path().string() + " --overlay " + (out / "overlay.gif").string() + " --out " +
                         out.path().string(),
                     &log),
            2)
      << log;
  EXPECT_NE(log.find("overlay.gif"), std::string::npos) << log;
}

// The libtorch backends inside `adugs run`: an ultralytics-interface TorchScript detector and
// MobileSAM-interface TorchScript encoder/decoder (tiny closed-form modules from the test
// scripts; doc/tracking.md). The detector reports a person at a fixed place scored by the red
// value of the image centre, which the simulator's grey images make about 0.5; the SAM-like
// decoder masks the bright pixels inside the box.
TEST_F(CmdRunVioSim, TorchScriptDetectorAndMobileSamRunTheDynamicStage) {
  const std::filesystem::path& ultralytics = pythonGenerated("tests/tracking/models/make_ultralytics_like_models.py");
  const std::filesystem::path& sam = pythonGenerated("tests/tracking/models/make_sam_like_torchscript.py");
  ASSERT_FALSE(ultralytics.empty() || sam.empty());
  TempDir out;
  std::string log;
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask detector --detector-model " +
                         (ultralytics / "detect.torchscript").string() + " --segmenter mobilesam --sam-encoder " +
                         (sam / "encoder.pt").string() + " --sam-decoder " + (sam / "decoder.pt").string() +
                         " --out " + out.path().string(),
                     &log),
            0)
      << log;
  const std::string summary = readFile(out / "summary.yaml");
  EXPECT_NE(summary.find("mask: detector"), std::string::npos) << summary;
  const size_t at = summary.find("masked_image_fraction: ");
  ASSERT_NE(at, std::string::npos) << summary;
  const double fraction = std::stod(summary.substr(at + 23));
  EXPECT_GT(fraction, 0.001) << summary;
  EXPECT_LT(fraction, 0.2) << summary;
  // The run config's dynamic: map: no SORT (the ablation) runs; bad keys and values are named.
  writeText(out / "no_sort.yaml", "dynamic:\n  tracker: none\n  dilate_radius_px: 4\n  high_score: 0.5\n"
                                  "  drop_unconfirmed: true\n  last_box_association: true\n  direction_weight: 0.2\n");
  ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask detector --detector-model " +
                         (ultralytics / "detect.torchscript").string() + " --segmenter box --config " +
                         (out / "no_sort.yaml").string() + " --out " + (out / "no_sort").string(),
                     &log),
            0)
      << log;
  const std::string no_sort = readFile(out / "no_sort" / "summary.yaml");
  const size_t no_sort_at = no_sort.find("masked_image_fraction: ");
  ASSERT_NE(no_sort_at, std::string::npos) << no_sort;
  EXPECT_GT(std::stod(no_sort.substr(no_sort_at + 23)), 0.001) << no_sort;
  for (const std::string& bad : {std::string("dynamic:\n  tracker: none\n  detect_every: 2\n"),
                                 std::string("dynamic:\n  noize: fixed\n"), std::string("dynamic:\n  noise: fxed\n"),
                                 std::string("dynamic:\n  high_score: 1.5\n")}) {
    writeText(out / "bad.yaml", bad);
    EXPECT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask detector --detector-model " +
                           (ultralytics / "detect.torchscript").string() + " --config " + (out / "bad.yaml").string() +
                           " --out " + (out / "bad").string(),
                       &log),
              2)
        << bad << log;
    EXPECT_NE(log.find("bad.yaml"), std::string::npos) << log;
  }
  // A decoder with the wrong interface stops the run before any frame, naming the file.
  EXPECT_EQ(runAdugs("run -q " + dir_->path().string() + " --mask detector --detector-model " +
                         (ultralytics / "detect.torchscript").string() + " --segmenter mobilesam --sam-encoder " +
                         (sam / "encoder.pt").string() + " --sam-decoder " +
                         (sam / "decoder_two_inputs.pt").string() + " --out " + out.path().string(),
                     &log),
            2)
      << log;
  EXPECT_NE(log.find("decoder_two_inputs.pt"), std::string::npos) << log;
  // The backends are libadugs_torch.so, opened when such a model is given: without it (or with
  // something else in its place) the run stops before any frame, naming the model and why.
  writeText(out / "not_a_module.so", "text\n");
  for (const auto& [module, why] : {std::pair<std::string, std::string>{"/nonexistent/libadugs_torch.so", "rebuild"},
                                    {(out / "not_a_module.so").string(), "cannot open"}}) {
    EXPECT_EQ(test::runCommand("ADUGS_TORCH_MODULE=" + module + " " + std::string(ADUGS_BINARY) + " run -q " +
                                   dir_->path().string() + " --mask detector --detector-model " +
                                   (ultralytics / "detect.torchscript").string() + " --out " + (out / "nomod").string(),
                               &log),
              2)
        << log;
    EXPECT_NE(log.find("detect.torchscript"), std::string::npos) << log;
    EXPECT_NE(log.find("libtorch"), std::string::npos) << log;
    EXPECT_NE(log.find(why), std::string::npos) << log;
  }
}

// The big optional libraries are never loaded by adugs itself: libtorch (about 160 MB resident
// and 0.3 s at every start) and OpenCV's imgcodecs and videoio (GDAL, ffmpeg, GStreamer: ~50 MB)
// are in modules beside the binary, opened when a TorchScript model, a video, a webcam or an
// image format other than PNG/JPEG is used. `ldd` lists everything the binary loads at start.
TEST(AdugsBinary, OptionalLibrariesAreModulesNotLinked) {
  std::string loaded;
  ASSERT_EQ(test::runCommand("ldd " + std::string(ADUGS_BINARY), &loaded), 0) << loaded;
  EXPECT_NE(loaded.find("libopencv_core"), std::string::npos) << loaded;
  for (const char* library : {"libtorch", "libc10", "libopencv_imgcodecs", "libopencv_videoio", "libgdal",
                              "libavcodec", "libvisp_io", "libvisp_detection"})
    EXPECT_EQ(loaded.find(library), std::string::npos) << library << " is loaded by adugs:\n" << loaded;
  const std::filesystem::path dir = std::filesystem::path(ADUGS_BINARY).parent_path();
  for (const auto& [module, library] : {std::pair{"libadugs_torch.so", "libtorch"},
                                        std::pair{"libadugs_media.so", "libopencv_videoio"},
                                        std::pair{"libadugs_media.so", "libopencv_imgcodecs"}}) {
    ASSERT_TRUE(std::filesystem::exists(dir / module)) << module << ": built beside the binary";
    std::string needed;
    ASSERT_EQ(test::runCommand("readelf -d " + (dir / module).string(), &needed), 0) << needed;
    EXPECT_NE(needed.find(library), std::string::npos) << module << " should link " << library << ":\n" << needed;
  }
}

// Acquisition, detection, masking, front-end and estimator run on threads of their own; the front-end's gyro
// prediction always uses the bias from two frames back, so two runs write the same bytes. The
// solver's wall-clock guard is for live sources only: set to 1 ms here, applied it would cut
// nearly every solve at a load-dependent point; playback ignores it.
TEST_F(CmdRunVioSim, ThreadedPipelineIsDeterministic) {
  TempDir a, b;
  writeText(a / "cfg.yaml", "estimator:\n  max_solver_time_s: 0.001\n");
  std::string log;
  for (const TempDir* out : {&a, &b})
    ASSERT_EQ(runAdugs("run -q " + dir_->path().string() + " --config " +
                           (a / "cfg.yaml").string() + " --out " + out->path().string(),
                       &log),
              0)
        << log;
  const std::string ta = readFile(a / "trajectory.tum"), tb = readFile(b / "trajectory.tum");
  EXPECT_GT(std::count(ta.begin(), ta.end(), '\n'), 80);
  EXPECT_EQ(ta, tb);
  EXPECT_NE(readFile(a / "summary.yaml").find("threads: 5"), std::string::npos);
  EXPECT_EQ(summaryText(a / "summary.yaml", "solver_time_guard_s").rfind("none  #", 0), 0u);
  EXPECT_EQ(summaryText(a / "summary.yaml", "solves_cut_by_time"), "0");
  // Steps per solve: at least one, at most max_iterations (8 by default).
  const double steps = std::stod(summaryText(a / "summary.yaml", "solver_steps_per_solve"));
  EXPECT_GE(steps, 1.0);
  EXPECT_LE(steps, 8.0);
}

// A corrupt image half-way: the front-end thread's error reaches the user (file named, exit 2)
// and the poses estimated before it stay in trajectory.tum.
TEST_F(CmdRunVioSim, CorruptImageMidwayStopsWithTheFileNamedAndKeepsEarlierPoses) {
  TempDir copy;
  std::filesystem::copy(dir_->path(), copy.path(), std::filesystem::copy_options::recursive);
  std::vector<std::filesystem::path> images;
  for (const auto& e : std::filesystem::directory_iterator(copy / "mav0" / "cam0" / "data"))
    images.push_back(e.path());
  std::sort(images.begin(), images.end());
  ASSERT_GT(images.size(), 100u);
  const auto bad = images[80];  // 4 s in, well after the initialisation at 1.5 s
  writeText(bad, "not a png");
  TempDir out;
  std::string log;
  EXPECT_EQ(runAdugs("run -q " + copy.path().string() + " --out " + out.path().string(), &log), 2)
      << log;
  EXPECT_NE(log.find(bad.filename().string()), std::string::npos) << log;
  const auto traj = data::readTrajectory((out / "trajectory.tum").string());
  EXPECT_GT(traj.size(), 30u);
}

TEST_F(CmdRunVioSim, BadConfigNamesTheKey) {
  TempDir out;
  // Each config must stop `adugs run` with exit 2 and an error naming the offending key.
  const auto expectRefused = [&](const std::string& name, const std::string& yaml,
                                 const std::string& key) {
    writeText(out / name, yaml);
    std::string log;
    EXPECT_EQ(runAdugs("run -q " + dir_->path().string() + " --config " + (out / name).string() +
                           " --out " + out.path().string(),
                       &log),
              2)
        << name << ": " << log;
    EXPECT_NE(log.find(key), std::string::npos) << name << ": " << log;
  };
  expectRefused("bad.yaml", "estimator:\n  window_size: 2\n", "window_size");
  expectRefused("typo.yaml", "tracker:\n  max_featurs: 100\n", "max_featurs");
  expectRefused("offset.yaml", "estimator:\n  estimate_time_offset: true\n  time_offset_s: 0.3\n",
                "time_offset_s");  // > max 0.1 s
  expectRefused("outlier.yaml", "estimator:\n  outlier_reprojection_px: -1\n",
                "outlier_reprojection_px");
  expectRefused("init_window.yaml", "estimator:\n  init_window_size: 6\n", "init_window_size");
  expectRefused("vi_bias.yaml", "estimator:\n  vi_init_accel_bias_sigma: -0.1\n", "vi_init_accel_bias_sigma");
  expectRefused("init_scale.yaml", "estimator:\n  init:\n    max_scale_relative_std: -0.1\n",
                "max_scale_relative_std");
  expectRefused("few_features.yaml", "estimator:\n  few_features_max_s: -1\n", "few_features_max_s");
}

}  // namespace
}  // namespace adugs::test

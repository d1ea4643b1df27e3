// End-to-end sequence generation: the EuRoC reader loads it, masks and MOT rows are there, the
// bytes are deterministic, hybrid mode follows the shared V1_01 data, bad input is an InputError.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/mot_io.h"
#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "data/sim/sim_sequence.h"
#include "data/sources/euroc_reader.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A double-sphere lens at half EuRoC's size (Basalt's EuRoC fit, halved): the --camera tests' lens.
CameraCalibration halfSizeDoubleSphere() {
  CameraCalibration ds;
  ds.width = 376, ds.height = 240;
  ds.fx = 174.85, ds.fy = 174.35, ds.cx = 182.9, ds.cy = 124.5;
  ds.projection = ProjectionModel::kDoubleSphere;
  ds.projection_params = {-0.2441, 0.5662};
  ds.distortion_model = DistortionModel::kNone;
  ds.distortion = {0, 0, 0, 0};
  ds.rate_hz = 20;
  return ds;
}

SimSequenceOptions smallOptions() {
  SimSequenceOptions o;
  o.scene = "street";
  o.level = SimLevel::kHigh;
  o.seed = 3;
  o.duration_s = 1.0;
  o.camera = SimCamera().scaled(0.5);  // small images keep the test fast
  o.progress = false;
  return o;
}

TEST(SimSequence, EurocReaderLoadsItWithMasksAndBoxes) {
  test::TempDir dir("adugs_sim");
  generateSimSequence(smallOptions(), dir.path().string());
  EurocReader reader(dir.path().string());
  int frames = 0, imu = 0;
  Measurement m;
  while (reader.next(m)) {
    if (m.isFrame()) {
      ++frames;
      EXPECT_EQ(m.frame.image.cols, 376);
      const fs::path mask = dir / ("mav0/mask0/data/" + std::to_string(m.frame.t_ns) + ".png");
      const cv::Mat mk = cv::imread(mask.string(), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(mk.empty()) << mask;
      EXPECT_EQ(mk.size(), m.frame.image.size());
    } else {
      ++imu;
    }
  }
  EXPECT_EQ(frames, 21);
  EXPECT_EQ(imu, 201);
  ASSERT_TRUE(reader.hasGroundTruth());
  const auto gt = readGroundTruthStates(reader.groundTruthPath());
  EXPECT_EQ(gt.size(), 201u);
  EXPECT_TRUE(gt[0].has_velocity_and_biases);
  EXPECT_NEAR(reader.camera().fx, SimCamera().fx / 2, 1e-9);

  // MOT rows: 9 columns, frames within range, visibility in [0, 1].
  std::ifstream mot(dir / "mav0/objects0/gt.txt");
  std::string line;
  int rows = 0;
  while (std::getline(mot, line)) {
    if (line.empty() || line[0] == '#') continue;
    int frame, id, x, y, w, h, conf, cls;
    double vis;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%d,%d,%d,%d,%d,%d,%lf", &frame, &id, &x, &y, &w, &h,
                          &conf, &cls, &vis), 9) << line;
    EXPECT_GE(frame, 1);
    EXPECT_LE(frame, 21);
    EXPECT_GT(w, 0);
    EXPECT_GE(vis, 0.0);
    EXPECT_LE(vis, 1.0);
    ++rows;
  }
  EXPECT_GT(rows, 10);
}

TEST(SimSequence, SameSeedSameBytes) {
  test::TempDir a("adugs_sim_a"), b("adugs_sim_b");
  SimSequenceOptions o = smallOptions();
  o.duration_s = 0.3;
  generateSimSequence(o, a.path().string());
  generateSimSequence(o, b.path().string());
  int compared = 0;
  for (const auto& e : fs::recursive_directory_iterator(a.path())) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), a.path());
    ASSERT_TRUE(fs::exists(b.path() / rel)) << rel;
    EXPECT_EQ(readAll(e.path()), readAll(b.path() / rel)) << rel;
    ++compared;
  }
  EXPECT_GT(compared, 10);
}

// A sequence's objects0/gt.txt rows (read by the project's MOT reader) as {frame, id, left, top,
// width, height, conf, class}: visibility dropped, as occluders change it.
std::vector<std::array<double, 8>> motRows(const fs::path& root) {
  std::vector<std::array<double, 8>> rows;
  for (const auto& [frame, boxes] : readMotFile((root / "mav0/objects0/gt.txt").string()))
    for (const MotBox& b : boxes)
      rows.push_back({double(frame), double(b.id), b.left, b.top, b.width, b.height, b.confidence, double(b.class_id)});
  return rows;
}

// Issue 30's scene with parked cars and people waiting: they are drawn and boxed, flagged "ignore"
// (conf 0) and left out of the dynamic masks; the moving objects of the seed do not change.
TEST(SimSequence, StandingObjectsAreDrawnButNotMasked) {
  test::TempDir dir("adugs_sim_standing");
  SimSequenceOptions o = smallOptions();
  o.duration_s = 0.5;
  o.level = SimLevel::kNone;
  o.standing = 6;
  std::set<double> classes;
  int masks = 0;
  for (const std::string scene : {"street", "room"}) {  // parked cars in the first 0.5 s; people
    o.scene = scene;
    generateSimSequence(o, (dir / ("none_" + scene)).string());
    for (const auto& r : motRows(dir / ("none_" + scene))) {
      EXPECT_EQ(r[6], 0) << scene << " frame " << r[0] << " object " << r[1] << " is not flagged static";
      classes.insert(r[7]);
    }
    for (const auto& e : fs::directory_iterator(dir / ("none_" + scene) / "mav0/mask0/data")) {
      EXPECT_EQ(cv::countNonZero(cv::imread(e.path().string(), cv::IMREAD_GRAYSCALE)), 0) << e.path();
      ++masks;
    }
  }
  EXPECT_EQ(classes, (std::set<double>{0, 2})) << "people and parked cars in view";
  EXPECT_EQ(masks, 22);
  o.scene = "street";
  const std::string info = readAll(dir / "none_street/mav0/sim.yaml");
  EXPECT_NE(info.find("class: car, coco_class: 2"), std::string::npos) << info;
  EXPECT_NE(info.find("moving: false"), std::string::npos) << info;

  // At level high the movers are the same with and without the standing objects.
  o.level = SimLevel::kHigh;
  generateSimSequence(o, (dir / "high_standing").string());
  o.standing = 0;
  generateSimSequence(o, (dir / "high").string());
  std::vector<std::array<double, 8>> movers;
  for (const auto& r : motRows(dir / "high_standing"))
    if (r[6] == 1) movers.push_back(r);
  EXPECT_FALSE(movers.empty());
  EXPECT_EQ(movers, motRows(dir / "high"));
}

TEST(SimSequence, HybridFollowsSharedV101) {
  const fs::path root = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(root);
  test::TempDir dir("adugs_sim_hybrid");
  SimSequenceOptions o = smallOptions();
  o.scene = "room";
  o.duration_s = 1.0;
  o.trajectory_path = (root / "groundtruth/V1_01_easy_vicon2gt.csv").string();
  o.imu_path = (root / "mav0/imu0/data.csv").string();
  o.calib_path = (root / "mav0/cam0/sensor.yaml").string();
  generateSimSequence(o, dir.path().string());
  EurocReader reader(dir.path().string());
  EXPECT_EQ(reader.camera().width, 752);
  EXPECT_NEAR(reader.camera().T_B_C.translation().x(), -0.0216401454975, 1e-12);
  int frames = 0;
  Measurement m;
  int64_t first_imu = -1;
  while (reader.next(m)) {
    frames += m.isFrame();
    if (m.isImu() && first_imu < 0) {
      first_imu = m.imu.t_ns;
      EXPECT_NEAR(m.imu.accel.x(), 9.0874956666666655, 1e-12);  // the real IMU, unchanged
    }
  }
  EXPECT_EQ(frames, 21);
  EXPECT_EQ(first_imu, 1403715273262142976);
}

// `adugs sim --calib` with an equidistant cam0/sensor.yaml (a TUM-VI-like 512x512 fisheye):
// the sequence carries the same calibration, its corners beyond the image circle are black and
// the centre sees the world.
TEST(SimSequence, HybridRendersAnEquidistantCalibration) {
  const fs::path root = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(root);
  test::TempDir dir("adugs_sim_fisheye");
  CameraCalibration fisheye = readEurocCameraYaml((root / "mav0/cam0/sensor.yaml").string());
  fisheye.width = fisheye.height = 512;
  fisheye.fx = 190.97847715128717;
  fisheye.fy = 190.9733070521226;
  fisheye.cx = 254.93170605935475;
  fisheye.cy = 256.8974428996504;
  fisheye.distortion_model = DistortionModel::kEquidistant;
  fisheye.distortion = {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
                        0.00020293673591811182};
  writeEurocCameraYaml((dir / "sensor.yaml").string(), fisheye);
  SimSequenceOptions o = smallOptions();
  o.scene = "room";
  o.duration_s = 0.5;
  o.trajectory_path = (root / "groundtruth/V1_01_easy_vicon2gt.csv").string();
  o.imu_path = (root / "mav0/imu0/data.csv").string();
  o.calib_path = (dir / "sensor.yaml").string();
  generateSimSequence(o, (dir / "seq").string());

  EurocReader reader((dir / "seq").string());
  EXPECT_EQ(reader.camera().distortion_model, DistortionModel::kEquidistant);
  EXPECT_EQ(reader.camera().distortion, fisheye.distortion);
  EXPECT_EQ(reader.camera().fx, fisheye.fx);
  int frames = 0;
  Measurement m;
  while (reader.next(m)) {
    if (!m.isFrame()) continue;
    ++frames;
    ASSERT_EQ(m.frame.image.size(), cv::Size(512, 512));
    EXPECT_LT(cv::mean(m.frame.image(cv::Rect(0, 0, 20, 20)))[0], 1.0) << "corner: noise only";
    EXPECT_GT(cv::mean(m.frame.image(cv::Rect(196, 196, 120, 120)))[0], 20) << "centre";
  }
  EXPECT_EQ(frames, 11);
}

// A wide-angle lens named in a cam0/sensor.yaml (--camera): the sequence is rendered through it
// and its written cam0/sensor.yaml reads back as the same camera, so `adugs run` uses it.
TEST(SimSequence, RendersThroughAGivenDoubleSphereCamera) {
  test::TempDir dir("adugs_sim_ds");
  const CameraCalibration ds = halfSizeDoubleSphere();
  writeEurocCameraYaml((dir / "ds.yaml").string(), ds);
  SimSequenceOptions o = smallOptions();
  o.duration_s = 0.5;
  o.camera_path = (dir / "ds.yaml").string();
  generateSimSequence(o, (dir / "seq").string());

  EurocReader reader((dir / "seq").string());
  const CameraCalibration& back = reader.camera();
  EXPECT_EQ(back.projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(back.projection_params, ds.projection_params);
  EXPECT_EQ(back.distortion_model, DistortionModel::kNone);
  EXPECT_EQ(back.distortion, ds.distortion);
  EXPECT_EQ(back.fx, ds.fx);
  EXPECT_EQ(back.cy, ds.cy);
  EXPECT_EQ(back.width, ds.width);
  // The written file is the one the simulator rendered with: reading it gives the same model.
  const CameraModel model(back);
  Eigen::Vector2d a, b;
  ASSERT_TRUE(model.project({1.2, -0.4, 0.5}, &a));
  ASSERT_TRUE(simCameraFromCalibration(ds, "ds.yaml").project({1.2, -0.4, 0.5}, &b));
  EXPECT_EQ(a, b);
  int frames = 0;
  Measurement m;
  while (reader.next(m)) {
    if (!m.isFrame()) continue;
    ++frames;
    ASSERT_EQ(m.frame.image.size(), cv::Size(376, 240));
    EXPECT_GT(cv::mean(m.frame.image)[0], 20) << "the world is seen";
  }
  EXPECT_EQ(frames, 11);
  EXPECT_NE(readAll(dir / "seq/mav0/sim.yaml").find("camera: "), std::string::npos);
}

// --camera takes any calibration file the product reads: a Kalibr camchain with a DS camera
// renders the same images as the same lens in a sensor.yaml.
TEST(SimSequence, RendersThroughTheFirstCameraOfAKalibrCamchain) {
  test::TempDir dir("adugs_sim_kalibr_ds");
  test::writeText(dir / "camchain.yaml",
                  "cam0:\n  camera_model: ds\n  intrinsics: [-0.2441, 0.5662, 174.85, 174.35, 182.9, 124.5]\n"
                  "  distortion_model: none\n  distortion_coeffs: []\n  resolution: [376, 240]\n"
                  "  rostopic: /cam0/image_raw\n");
  const CameraCalibration ds = halfSizeDoubleSphere();
  writeEurocCameraYaml((dir / "ds.yaml").string(), ds);
  SimSequenceOptions o = smallOptions();
  o.duration_s = 0.2;
  o.camera_path = (dir / "camchain.yaml").string();
  generateSimSequence(o, (dir / "kalibr").string());
  o.camera_path = (dir / "ds.yaml").string();
  generateSimSequence(o, (dir / "euroc").string());
  EurocReader a((dir / "kalibr").string()), b((dir / "euroc").string());
  EXPECT_EQ(a.camera().projection, ProjectionModel::kDoubleSphere);
  EXPECT_EQ(a.camera().projection_params, ds.projection_params);
  Measurement ma, mb;
  int frames = 0;
  while (a.next(ma) && b.next(mb)) {
    if (!ma.isFrame()) continue;
    ++frames;
    EXPECT_EQ(cv::norm(ma.frame.image, mb.frame.image, cv::NORM_INF), 0) << "frame " << frames;
  }
  EXPECT_GT(frames, 2);
}

// A given imu0/sensor.yaml sets the noise the synthetic IMU is drawn with, and the written
// sensor.yaml carries it on to the estimator.
TEST(SimSequence, SimulatesTheGivenImuNoiseFigures) {
  test::TempDir dir("adugs_sim_imu_noise");
  ImuNoise given;
  given.rate_hz = 200;
  given.gyro_noise_density = 2e-3;
  given.gyro_random_walk = 1e-9;
  given.accel_noise_density = 2e-2;
  given.accel_random_walk = 0.3;  // 100x EuRoC's, so the walk shows within the short sequence
  writeEurocImuYaml((dir / "imu.yaml").string(), given);
  SimSequenceOptions o = smallOptions();
  o.level = SimLevel::kNone;
  o.duration_s = 0.5;
  o.imu_calib_path = (dir / "imu.yaml").string();
  generateSimSequence(o, (dir / "seq").string());

  EurocReader reader((dir / "seq").string());
  EXPECT_DOUBLE_EQ(reader.imuNoise().accel_random_walk, 0.3);
  EXPECT_DOUBLE_EQ(reader.imuNoise().gyro_noise_density, 2e-3);
  const std::vector<GroundTruthState> truth =
      readGroundTruthStates((dir / "seq/mav0/state_groundtruth_estimate0/data.csv").string());
  ASSERT_GT(truth.size(), 90u);
  double sum_sq = 0, gyro_change = 0;
  int n = 0;
  for (size_t k = 1; k < truth.size(); ++k, n += 3) {
    sum_sq += (truth[k].accel_bias - truth[k - 1].accel_bias).squaredNorm();
    gyro_change = std::max(gyro_change, (truth[k].gyro_bias - truth[0].gyro_bias).norm());
  }
  // Per-sample bias steps have sigma = random_walk * sqrt(dt).
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.3 * std::sqrt(1.0 / 200), 0.2 * 0.3 * std::sqrt(1.0 / 200));
  EXPECT_LT(gyro_change, 1e-6);

  test::writeText(dir / "bad.yaml", "%YAML:1.0\nsensor_type: imu\nrate_hz: 200\n");
  o.imu_calib_path = (dir / "bad.yaml").string();
  try {
    generateSimSequence(o, (dir / "bad").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
  }
}

// "handheld" walks the same glide path with the rig in hand: it stays within a few centimetres
// of the glide path but accelerates an order of magnitude more (the step bob).
TEST(SimSceneTrajectory, HandheldAddsStepBobToTheSameGlidePath) {
  for (const std::string scene : {"room", "street", "courtyard"}) {
    const int64_t t0 = kSimDefaultStartNs, t1 = t0 + secToNs(20);
    const SineTrajectory glide = makeSceneTrajectory(scene, 4, t0, t1);
    const SineTrajectory hand = makeSceneTrajectory(scene, 4, t0, t1, "handheld");
    double max_offset = 0, sum_a_glide = 0, sum_a_hand = 0;
    int n = 0;
    for (int64_t t = t0; t <= t1; t += secToNs(0.01), ++n) {
      const SimBodyState g = glide.stateAt(t), h = hand.stateAt(t);
      max_offset = std::max(max_offset, (h.p_W_B - g.p_W_B).norm());
      sum_a_glide += g.a_W.squaredNorm();
      sum_a_hand += h.a_W.squaredNorm();
    }
    EXPECT_GT(max_offset, 0.015) << scene;
    EXPECT_LT(max_offset, 0.05) << scene;
    EXPECT_LT(std::sqrt(sum_a_glide / n), 0.5) << scene;
    EXPECT_GT(std::sqrt(sum_a_hand / n), 1.2) << scene;
  }
  EXPECT_THROW(checkSimMotionName("jog"), InputError);
}

TEST(SimSequence, BadInputIsInputError) {
  EXPECT_THROW(parseSimLevel("extreme"), InputError);
  test::TempDir dir("adugs_sim_bad");
  SimSequenceOptions o = smallOptions();
  o.scene = "moon";
  EXPECT_THROW(generateSimSequence(o, dir.path().string()), InputError);

  const fs::path root = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(root);
  o = smallOptions();
  o.trajectory_path = (dir / "missing.csv").string();
  o.imu_path = (root / "mav0/imu0/data.csv").string();
  o.calib_path = (root / "mav0/cam0/sensor.yaml").string();
  EXPECT_THROW(generateSimSequence(o, (dir / "out").string()), InputError);
  o.trajectory_path = (root / "groundtruth/V1_01_easy_vicon2gt.csv").string();
  o.motion = "handheld";  // hybrid follows the given path: a motion would be silently ignored
  try {
    generateSimSequence(o, (dir / "out_motion").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--motion"), std::string::npos) << e.what();
  }
  o.motion = "glide";
  o.trajectory_path = (dir / "missing.csv").string();
  SimSequenceOptions standing = smallOptions();
  standing.standing = -1;
  try {
    generateSimSequence(standing, (dir / "out_standing").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--standing"), std::string::npos) << e.what();
  }

  // An IMU stream that stops after 0.5 s cannot serve a 1 s trajectory.
  std::ifstream in(root / "mav0/imu0/data.csv");
  std::string text, line;
  for (int i = 0; i < 101 && std::getline(in, line); ++i) text += line + "\n";
  test::writeText(dir / "short_imu.csv", text);
  o.trajectory_path = (root / "groundtruth/V1_01_easy_vicon2gt.csv").string();
  o.imu_path = (dir / "short_imu.csv").string();
  try {
    generateSimSequence(o, (dir / "out2").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not cover"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adugs::data

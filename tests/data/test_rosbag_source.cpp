// ROS1 bag playback: bags written by the real rosbag library (Debian's python3-rosbag, from a
// simulated ASL sequence) in the VIODE, EuRoC and OpenLORIS layouts, plain / bz2 / lz4, stream
// exactly what the ASL folder streams; the real T265 bag and the rosbag.js fixtures give the
// right contents or clean errors.
#include <filesystem>
#include <functional>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "data/sim/sim_sequence.h"
#include "data/sources/dataset_preset.h"
#include "data/sources/euroc_reader.h"
#include "data/sources/rosbag_ground_truth.h"
#include "data/sources/rosbag_info.h"
#include "data/sources/rosbag_source.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

std::vector<Measurement> readAll(SequenceSource& source) {
  std::vector<Measurement> all;
  Measurement m;
  while (source.next(m)) all.push_back(m);
  return all;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// One small simulated sequence (2 s, 376x240, IMU at 400 Hz) and its bags, made once.
class RosbagPlayback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("adugs_rosbag");
    SimSequenceOptions o;
    o.scene = "room";
    o.level = SimLevel::kMid;
    o.seed = 2;
    o.duration_s = 2.0;
    o.camera = SimCamera().scaled(0.5);
    o.imu.rate_hz = 400;
    o.progress = false;
    generateSimSequence(o, asl().string());
    std::string log;
    auto write = [&](const std::string& name, const std::string& args) {
      ASSERT_EQ(test::writeTestBag(asl().string() + " " + (*dir_ / name).string() + " " + args, &log), 0) << log;
    };
    write("viode.bag", "--layout viode --kalibr-out " + (*dir_ / "kalibr").string());
    for (const char* c : {"none", "bz2", "lz4"})
      write(std::string("euroc_") + c + ".bag", std::string("--layout euroc --compression ") + c);
    write("openloris.bag", "--layout openloris");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path asl() { return *dir_ / "asl"; }
  static std::string bag(const std::string& name) { return (*dir_ / name).string(); }

  static RosbagSourceOptions singleImu() {
    RosbagSourceOptions o;
    o.topics.image = "/cam0/image_raw";
    o.topics.imu = "/imu0";
    return o;
  }
  static test::TempDir* dir_;
};
test::TempDir* RosbagPlayback::dir_ = nullptr;

void expectSameStream(const std::vector<Measurement>& expected, const std::vector<Measurement>& got) {
  ASSERT_EQ(expected.size(), got.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const Measurement& e = expected[i];
    const Measurement& g = got[i];
    ASSERT_EQ(e.type, g.type) << i;
    ASSERT_EQ(e.timeNs(), g.timeNs()) << i;
    if (e.isImu()) {
      EXPECT_EQ(e.imu.gyro, g.imu.gyro) << i;
      EXPECT_EQ(e.imu.accel, g.imu.accel) << i;
    } else {
      ASSERT_EQ(e.frame.image.size(), g.frame.image.size());
      EXPECT_EQ(cv::norm(e.frame.image, g.frame.image, cv::NORM_INF), 0.0) << "frame " << i;
    }
  }
}

TEST_F(RosbagPlayback, ViodeAndEurocLayoutsStreamExactlyTheAslSequence) {
  EurocReader reader(asl().string());
  const std::vector<Measurement> expected = readAll(reader);
  for (const std::string name : {"viode.bag", "euroc_none.bag", "euroc_bz2.bag", "euroc_lz4.bag"}) {
    SCOPED_TRACE(name);
    RosbagSource source(bag(name), singleImu());
    expectSameStream(expected, readAll(source));
    // Images were recorded 5-30 ms after their stamps: the reorder window put them back.
    EXPECT_EQ(source.counts().late_dropped, 0u);
    EXPECT_EQ(source.counts().imu_dropped, 0u);
  }
}

TEST_F(RosbagPlayback, WithoutAReorderWindowDelayedImagesComeTooLate) {
  RosbagSourceOptions o = singleImu();
  o.reorder_window_ns = 0;
  RosbagSource source(bag("viode.bag"), o);
  const auto all = readAll(source);
  EXPECT_GT(source.counts().late_dropped, 20u);  // most of the 41 images
  for (size_t i = 1; i < all.size(); ++i) ASSERT_GE(all[i].timeNs(), all[i - 1].timeNs());
}

TEST_F(RosbagPlayback, OpenLorisSplitImuIsUnitedOnTheGyroStamps) {
  EurocReader reader(asl().string());
  std::vector<Measurement> expected = readAll(reader);
  RosbagSourceOptions o;
  o.topics.image = "/d400/color/image_raw";
  o.topics.accel = "/d400/accel/sample";
  o.topics.gyro = "/d400/gyro/sample";
  RosbagSource source(bag("openloris.bag"), o);
  const std::vector<Measurement> got = readAll(source);
  // The accelerometer (250 Hz) starts 1 ms after the first gyro stamp and ends up to 4 ms before
  // the last: those gyro samples have no accelerometer neighbours.
  EXPECT_GE(source.counts().unmatched_gyro, 1u);
  EXPECT_LE(source.counts().unmatched_gyro, 4u);
  size_t frames = 0, imu = 0;
  size_t j = 0;
  for (const Measurement& g : got) {
    while (j < expected.size() && expected[j].timeNs() != g.timeNs()) ++j;
    ASSERT_LT(j, expected.size()) << "stamp " << g.timeNs() << " is not in the ASL sequence";
    while (j < expected.size() && expected[j].type != g.type) ++j;  // IMU before frame on ties
    const Measurement& e = expected[j];
    if (g.isFrame()) {
      ++frames;
      EXPECT_EQ(cv::norm(e.frame.image, g.frame.image, cv::NORM_INF), 0.0);  // rgb8 of a grey image
    } else {
      ++imu;
      EXPECT_EQ(e.imu.gyro, g.imu.gyro);
      // Resampled at 250 Hz and back: the white noise (0.04 m/s^2 per 400 Hz sample) is smoothed.
      EXPECT_LT((e.imu.accel - g.imu.accel).norm(), 0.25);
    }
    ++j;
  }
  EXPECT_EQ(frames, 41u);
  EXPECT_GE(imu, 795u);
}

TEST_F(RosbagPlayback, GroundTruthOdometryMatchesTheAslFile) {
  const BagGroundTruth gt = readBagGroundTruth(bag("viode.bag"), {"/odometry", "", ""});
  const Trajectory expected = readTrajectory((asl() / "mav0/state_groundtruth_estimate0/data.csv").string());
  ASSERT_EQ(gt.poses.size(), expected.size());
  for (size_t i = 0; i < expected.size(); i += 37) {
    EXPECT_EQ(gt.poses[i].t_ns, expected[i].t_ns);
    EXPECT_LT((gt.poses[i].p_W_B - expected[i].p_W_B).norm(), 1e-12);
    EXPECT_LT(gt.poses[i].q_W_B.angularDistance(expected[i].q_W_B), 1e-9);
  }
  EXPECT_EQ(gt.duplicates_dropped, 0u);
}

TEST_F(RosbagPlayback, PresetWithKalibrFilesOpensTheBagAndWritesItsGroundTruth) {
  test::TempDir out("adugs_rosbag_out");
  PlaybackOptions o;
  o.dataset = "viode";
  o.path = bag("viode.bag");
  o.calibration = {(*dir_ / "kalibr/camchain-imucam.yaml").string(), (*dir_ / "kalibr/imu.yaml").string()};
  OpenedSequence s = openSequence(o, out.path().string());
  EXPECT_EQ(s.camera.width, 376);
  EXPECT_EQ(s.gt_path, (out / "groundtruth.tum").string());
  EXPECT_GT(readTrajectory(s.gt_path).size(), 300u);
  // The calibration round trip: T_B_C from T_cam_imu^-1 equals the folder's T_BS.
  const CameraCalibration asl_camera = readEurocCameraYaml((asl() / "mav0/cam0/sensor.yaml").string());
  EXPECT_LT((s.camera.T_B_C.matrix() - asl_camera.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(readAll(*s.source).size(), 41u + 801u);

  // The bag's images are 376x240; the preset's own VIODE calibration says 752x480.
  o.calibration.clear();
  OpenedSequence wrong = openSequence(o, out.path().string());
  const std::string err = errorOf([&] { readAll(*wrong.source); });
  EXPECT_NE(err.find("376x240"), std::string::npos) << err;
  EXPECT_NE(err.find("752x480"), std::string::npos) << err;
}

TEST_F(RosbagPlayback, OpenLorisPresetTakesTheGroundTruthFileBesideTheBag) {
  test::TempDir seq("adugs_openloris_seq"), out("adugs_openloris_out");
  fs::create_symlink(bag("openloris.bag"), seq / "office1-1.bag");
  PlaybackOptions o;
  o.dataset = "openloris";
  o.path = (seq / "office1-1.bag").string();
  o.calibration = {(*dir_ / "kalibr/camchain-imucam.yaml").string(), (*dir_ / "kalibr/imu.yaml").string()};
  EXPECT_EQ(openSequence(o, out.path().string()).gt_path, "");  // no file, no /gt topic: none
  const Trajectory gt = readTrajectory((asl() / "mav0/state_groundtruth_estimate0/data.csv").string());
  writeTumTrajectory((seq / "groundtruth.txt").string(), gt);
  const OpenedSequence s = openSequence(o, out.path().string());
  EXPECT_EQ(s.gt_path, (seq / "groundtruth.txt").string());
  EXPECT_EQ(readTrajectory(s.gt_path).size(), gt.size());
  // A ground-truth topic the user names wins over the file.
  o.gt_topic = "/d400/gyro/sample";  // exists, but is no pose type: named in the error
  try {
    openSequence(o, out.path().string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gt_topic"), std::string::npos) << e.what();
  }
}

TEST_F(RosbagPlayback, UnknownTopicListsTheBagsTopics) {
  RosbagSourceOptions o = singleImu();
  o.topics.imu = "/imu_missing";
  const std::string err = errorOf([&] { RosbagSource(bag("euroc_none.bag"), o); });
  EXPECT_NE(err.find("euroc_none.bag"), std::string::npos) << err;
  EXPECT_NE(err.find("imu_topic"), std::string::npos) << err;
  EXPECT_NE(err.find("/imu_missing"), std::string::npos) << err;
  EXPECT_NE(err.find("/cam0/image_raw (sensor_msgs/Image)"), std::string::npos) << err;
  EXPECT_NE(err.find("/imu0 (sensor_msgs/Imu)"), std::string::npos) << err;

  o.topics.imu = "/cam0/image_raw";  // exists, wrong type
  const std::string type_err = errorOf([&] { RosbagSource(bag("euroc_none.bag"), o); });
  EXPECT_NE(type_err.find("has type sensor_msgs/Image, expected sensor_msgs/Imu"), std::string::npos) << type_err;
}

TEST_F(RosbagPlayback, BagInfoCountsTopicsAndCompression) {
  const BagInfo plain = readBagInfo(bag("euroc_none.bag"));
  const BagInfo bz2 = readBagInfo(bag("euroc_bz2.bag"));
  EXPECT_EQ(plain.messages, 41u + 801u);
  EXPECT_EQ(bz2.messages, plain.messages);
  EXPECT_EQ(plain.chunks_by_compression.count("none"), 1u);
  EXPECT_EQ(bz2.chunks_by_compression.count("bz2"), 1u);
  EXPECT_EQ(readBagInfo(bag("euroc_lz4.bag")).chunks_by_compression.count("lz4"), 1u);
  ASSERT_EQ(plain.topics.size(), 2u);
  EXPECT_EQ(plain.topics[1].name, "/imu0");
  EXPECT_NEAR(plain.topics[1].rate_hz, 400.0, 5.0);
  EXPECT_NEAR(plain.topics[0].rate_hz, 20.0, 1.0);
}

// ---- real third-party bags ----

fs::path t265Bag() { return test::sharedDataDir() / "rosbags/kapture_t265/trimmed_locoffice.bag"; }
fs::path fixtures() { return test::sharedDataDir() / "rosbags/rosbagjs_fixtures"; }

TEST(RosbagRealBags, T265RecordingPlaysEveryImageAndUnitesItsImu) {
  ADUGS_REQUIRE_SHARED(t265Bag());
  const BagInfo info = readBagInfo(t265Bag().string());
  EXPECT_EQ(info.messages, 50u);
  ASSERT_EQ(info.topics.size(), 5u);
  EXPECT_EQ(info.topics[0].name, "/camera/accel/sample");
  EXPECT_EQ(info.topics[0].messages, 6u);
  EXPECT_EQ(info.topics[3].name, "/camera/gyro/sample");
  EXPECT_EQ(info.topics[3].messages, 19u);
  EXPECT_EQ(info.topics[4].type, "nav_msgs/Odometry");

  RosbagSourceOptions o;
  o.topics = {"/camera/fisheye1/image_raw", "", "/camera/accel/sample", "/camera/gyro/sample"};
  o.expected_width = 848;
  o.expected_height = 800;
  RosbagSource source(t265Bag().string(), o);
  size_t frames = 0, imu = 0;
  int64_t last = 0;
  for (const Measurement& m : readAll(source)) {
    EXPECT_GE(m.timeNs(), last);
    last = m.timeNs();
    if (m.isFrame()) {
      ++frames;
      EXPECT_EQ(m.frame.image.type(), CV_8UC1);
      EXPECT_GT(cv::mean(m.frame.image)[0], 5.0);  // a real picture, not zeros
    } else {
      ++imu;
      EXPECT_NEAR(m.imu.accel.norm(), 9.8, 1.0);  // the camera sits still: gravity only
    }
  }
  EXPECT_EQ(frames, 3u);
  // Every gyro sample between the first and last accelerometer sample (62.5 Hz) is united.
  EXPECT_EQ(imu + source.counts().unmatched_gyro, 19u);
  EXPECT_GE(imu, 12u);

  const BagGroundTruth gt = readBagGroundTruth(t265Bag().string(), {"/camera/odom/sample", "", ""});
  EXPECT_EQ(gt.poses.size(), 19u);
}

TEST(RosbagRealBags, CompressedFixturesReadLikeThePlainOne) {
  ADUGS_REQUIRE_SHARED(fixtures());
  const BagInfo plain = readBagInfo((fixtures() / "example.bag").string());
  EXPECT_EQ(plain.messages, 8647u);
  for (const char* name : {"example-bz2.bag", "example-lz4.bag"}) {
    const BagInfo c = readBagInfo((fixtures() / name).string());
    EXPECT_EQ(c.messages, plain.messages) << name;
    ASSERT_EQ(c.topics.size(), plain.topics.size());
    for (size_t i = 0; i < c.topics.size(); ++i) EXPECT_EQ(c.topics[i].messages, plain.topics[i].messages);
  }
  EXPECT_EQ(readBagInfo((fixtures() / "example-bz2.bag").string()).chunks_by_compression.count("bz2"), 1u);
  EXPECT_EQ(readBagInfo((fixtures() / "example-unsorted-chunks.bag").string()).messages, 3u);
  // The turtlesim bag has a /tf topic: ground truth from tf2 needs named frames.
  EXPECT_NE(errorOf([&] { readBagGroundTruth((fixtures() / "example.bag").string(), {"/tf_static", "", ""}); })
                .find("parent and child frame"),
            std::string::npos);
}

TEST(RosbagRealBags, BrokenBagsAreCleanErrorsNamingTheFile) {
  ADUGS_REQUIRE_SHARED(fixtures());
  const std::string empty = (fixtures() / "empty-file.bag").string();
  EXPECT_NE(errorOf([&] { readBagInfo(empty); }).find(empty + ": empty file"), std::string::npos);
  // A bag with no messages: info works, playback names the missing topic.
  const std::string none = (fixtures() / "no-messages.bag").string();
  EXPECT_EQ(readBagInfo(none).messages, 0u);
  RosbagSourceOptions o;
  o.topics.image = "/cam0/image_raw";
  o.topics.imu = "/imu0";
  const std::string err = errorOf([&] { RosbagSource(none, o); });
  EXPECT_NE(err.find("is not in the bag"), std::string::npos) << err;
  // A recording cut short (no index at the end).
  test::TempDir dir("adugs_badbag");
  const fs::path cut = dir / "cut.bag";
  {
    std::ifstream in(fixtures() / "example.bag", std::ios::binary);
    std::string bytes(400000, '\0');
    in.read(bytes.data(), bytes.size());
    std::ofstream(cut, std::ios::binary).write(bytes.data(), bytes.size());
  }
  const std::string cut_err = errorOf([&] { readBagInfo(cut.string()); });
  EXPECT_NE(cut_err.find(cut.string() + ": not a readable ROS1 bag"), std::string::npos) << cut_err;
  // Not a bag at all.
  const std::string text_err = errorOf([&] { readBagInfo((fixtures() / "LICENSE.rosbag.js-Apache2.txt").string()); });
  EXPECT_NE(text_err.find("not a readable ROS1 bag"), std::string::npos) << text_err;
}

}  // namespace
}  // namespace adugs::data

namespace adugs::data {
namespace {

// IMU stamps that repeat or go backwards (a driver hiccup), written by the C++ rosbag library:
// within the reorder window a backwards sample is put back in order; a repeated stamp is dropped
// and counted; a sample older than what was already released is dropped as late.
TEST(RosbagImuStamps, RepeatedAndLateSamplesAreDroppedAndCounted) {
  test::TempDir dir("adugs_imu_stamps");
  const std::string path = (dir / "imu.bag").string();
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    const ros::Time t0(1700000000, 0);
    auto imu = [&](double t_s, double record_s) {
      sensor_msgs::Imu m;
      m.header.stamp = t0 + ros::Duration(t_s);
      m.linear_acceleration.z = 9.81;
      bag.write("/imu0", t0 + ros::Duration(record_s), m);
    };
    sensor_msgs::Image image;
    image.width = 4;
    image.height = 2;
    image.encoding = "mono8";
    image.step = 4;
    image.data.assign(8, 128);
    for (int k = 0; k < 40; ++k) {
      const double t = 0.005 * k;
      imu(t, t);
      if (k == 10) imu(t, t + 0.0001);         // the same stamp again: dropped
      if (k == 20) imu(t - 0.0025, t + 0.0001);  // 2.5 ms back, inside the window: reordered
      if (k % 10 == 5) {
        image.header.stamp = t0 + ros::Duration(t);
        bag.write("/cam0/image_raw", t0 + ros::Duration(t + 0.0002), image);
      }
    }
    imu(0.05, 0.3);  // recorded far too late for its stamp: the window has passed it
    bag.close();
  }
  RosbagSourceOptions o;
  o.topics.image = "/cam0/image_raw";
  o.topics.imu = "/imu0";
  o.reorder_window_ns = 20'000'000;
  RosbagSource source(path, o);
  size_t imu = 0, frames = 0;
  int64_t last = 0;
  Measurement m;
  while (source.next(m)) {
    EXPECT_GT(m.timeNs(), last - (m.isFrame() ? 1 : 0));
    last = m.timeNs();
    m.isImu() ? ++imu : ++frames;
  }
  EXPECT_EQ(frames, 4u);
  EXPECT_EQ(imu, 41u);  // 40 + the reordered one
  EXPECT_EQ(source.counts().imu_dropped, 1u);
  EXPECT_EQ(source.counts().late_dropped, 1u);
}

}  // namespace
}  // namespace adugs::data

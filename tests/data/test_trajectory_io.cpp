// Trajectory files: format detection, round trips, and every kind of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

using adugs::test::TempDir;
using adugs::test::writeText;

// Expects readTrajectory(path) to throw an InputError located at `line` (0: none) whose message
// contains `fragment`; returns the message.
std::string expectError(const std::filesystem::path& path, long line, const std::string& fragment) {
  try {
    readTrajectory(path.string());
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return "";
}

Trajectory makeTrajectory() {
  Trajectory t;
  for (int i = 0; i < 20; ++i) {
    StampedPose p;
    p.t_ns = 1403715273262142976LL + i * 50000123LL;
    p.p_W_B = Eigen::Vector3d(0.1 * i + 1.0 / 3.0, -2.0 * i + 1e-9, std::sin(i) * 1e3);
    p.q_W_B = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    t.push_back(p);
  }
  return t;
}

const char* kEurocHeader = "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n";

TEST(TrajectoryIo, TumRoundTripIsExact) {
  TempDir dir;
  const Trajectory in = makeTrajectory();
  const std::string path = (dir / "traj.txt").string();
  writeTumTrajectory(path, in);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  TrajectoryFormat format;
  const Trajectory out = readTrajectory(path, &format);
  EXPECT_EQ(format, TrajectoryFormat::kTum);
  ASSERT_EQ(out.size(), in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i].t_ns, in[i].t_ns);    // 9 decimals: nanoseconds survive exactly
    EXPECT_EQ(out[i].p_W_B, in[i].p_W_B);  // 17 significant digits: doubles survive exactly
    EXPECT_NEAR(out[i].q_W_B.angularDistance(in[i].q_W_B), 0.0, 1e-15);
  }
}

TEST(TrajectoryIo, TumLineFormat) {
  StampedPose p;
  p.t_ns = 1403715273262142976LL;
  p.p_W_B = Eigen::Vector3d(1.5, -0.25, 0.1);
  p.q_W_B = Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5);  // w, x, y, z
  EXPECT_EQ(formatTumLine(p),
            "1403715273.262142976 1.5 -0.25 0.10000000000000001 0.5 -0.5 0.5 0.5");
  p.t_ns = -1500000000LL;
  EXPECT_EQ(formatTumLine(p).substr(0, 13), "-1.500000000 ");
}

TEST(TrajectoryIo, WriterFlushesEachLine) {
  TempDir dir;
  const auto path = dir / "live.txt";
  TumTrajectoryWriter writer(path.string());
  const Trajectory t = makeTrajectory();
  writer.write(t[0]);
  writer.write(t[1]);
  // Without close(): what a killed process leaves behind must already be readable.
  const Trajectory partial = readTrajectory(path.string());
  ASSERT_EQ(partial.size(), 2u);
  EXPECT_EQ(partial[1].t_ns, t[1].t_ns);
  EXPECT_EQ(writer.count(), 2u);
  EXPECT_THROW(writer.write(t[1]), std::invalid_argument);  // not after the previous pose
  writer.close();
}

TEST(TrajectoryIo, WriterFailsOnUnwritablePath) {
  TempDir dir;
  EXPECT_THROW(TumTrajectoryWriter((dir / "no_such_dir" / "x.txt").string()), InputError);
  EXPECT_THROW(writeTumTrajectory((dir / "no_such_dir" / "x.txt").string(), makeTrajectory()),
               InputError);
}

TEST(TrajectoryIo, ReadsEuroc17ColumnsWithStates) {
  TempDir dir;
  const auto path = dir / "gt.csv";
  writeText(path, std::string(kEurocHeader) +
                      "1000,1,2,3,1,0,0,0,0.1,0.2,0.3,0.01,0.02,0.03,-0.1,-0.2,-0.3\n"
                      "2000,1.5,2,3,0,1,0,0,0.1,0.2,0.3,0.01,0.02,0.03,-0.1,-0.2,-0.3\n");
  TrajectoryFormat format;
  const Trajectory t = readTrajectory(path.string(), &format);
  EXPECT_EQ(format, TrajectoryFormat::kEurocCsv);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].t_ns, 2000);
  EXPECT_EQ(t[1].p_W_B, Eigen::Vector3d(1.5, 2, 3));
  EXPECT_DOUBLE_EQ(t[1].q_W_B.x(), 1.0);  // qw is first in EuRoC: (0,1,0,0) is x
  const auto states = readGroundTruthStates(path.string());
  ASSERT_EQ(states.size(), 2u);
  EXPECT_TRUE(states[0].has_velocity_and_biases);
  EXPECT_EQ(states[0].v_W, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(states[0].gyro_bias, Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_EQ(states[0].accel_bias, Eigen::Vector3d(-0.1, -0.2, -0.3));
}

TEST(TrajectoryIo, ReadsEuroc8ColumnsAndHeaderWithoutHash) {
  TempDir dir;
  const auto path = dir / "gt.csv";
  writeText(path,
            "timestamp, p_x, p_y, p_z, q_w, q_x, q_y, q_z\n1000, 1, 2, 3, 1, 0, 0, "
            "0\n2000,1,2,3,1,0,0,0");
  const auto states = readGroundTruthStates(path.string());
  ASSERT_EQ(states.size(), 2u);  // last line without '\n' still read
  EXPECT_FALSE(states[0].has_velocity_and_biases);
  EXPECT_EQ(detectTrajectoryFormat(path.string()), TrajectoryFormat::kEurocCsv);
}

TEST(TrajectoryIo, TumQuaternionOrderAndTimeParsing) {
  TempDir dir;
  const auto path = dir / "est.txt";
  writeText(path,
            "# t tx ty tz qx qy qz qw\n"
            "1.5 1 2 3 0 0 0 1\n"
            "\n"
            "1.6000000004\t1 2 3 1 0 0 0\n"
            "1.7e0 1 2 3 0 0 0 1\n");
  const Trajectory t = readTrajectory(path.string());
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].t_ns, 1500000000LL);
  EXPECT_EQ(t[1].t_ns, 1600000000LL);  // rounded at the 10th decimal
  EXPECT_EQ(t[2].t_ns, 1700000000LL);
  EXPECT_DOUBLE_EQ(t[0].q_W_B.w(), 1.0);  // qw last in TUM
  EXPECT_DOUBLE_EQ(t[1].q_W_B.x(), 1.0);
}

TEST(TrajectoryIo, QuaternionIsNormalisedWhenNearlyUnit) {
  TempDir dir;
  const auto path = dir / "est.txt";
  writeText(path, "1.0 0 0 0 0 0 0 1.004\n");
  const Trajectory t = readTrajectory(path.string());
  EXPECT_DOUBLE_EQ(t[0].q_W_B.norm(), 1.0);
}

TEST(TrajectoryIo, RealEurocGroundTruth) {
  const auto path =
      adugs::test::sharedDataDir() / "euroc_v101_micro/groundtruth/V1_01_easy_vicon2gt.csv";
  ADUGS_REQUIRE_SHARED(path);
  TrajectoryFormat format;
  const Trajectory t = readTrajectory(path.string(), &format);
  EXPECT_EQ(format, TrajectoryFormat::kEurocCsv);
  ASSERT_EQ(t.size(), 2895u);
  EXPECT_EQ(t.front().t_ns, 1403715273262142976LL);
  EXPECT_NEAR(t.front().p_W_B.x(), 0.878895, 1e-12);
  EXPECT_NEAR(t.front().q_W_B.w(), 0.069433, 1e-5);  // normalised from the file's 6 digits
  EXPECT_NEAR(t.front().q_W_B.x(), -0.824237, 1e-5);
  const auto states = readGroundTruthStates(path.string());
  EXPECT_TRUE(states.front().has_velocity_and_biases);
  EXPECT_NEAR(states.front().accel_bias.z(), 0.0309774, 1e-12);

  // EuRoC -> TUM -> read back: same poses.
  TempDir dir;
  writeTumTrajectory((dir / "v101.txt").string(), t);
  const Trajectory back = readTrajectory((dir / "v101.txt").string());
  ASSERT_EQ(back.size(), t.size());
  EXPECT_EQ(back.back().t_ns, t.back().t_ns);
  EXPECT_EQ(back.back().p_W_B, t.back().p_W_B);
}

TEST(TrajectoryIo, DuplicateTimestampsKeepTheFirstPose) {
  // Two poses share 2.0 s (line 3 kept, line 4 dropped), three share 4.0 s (5 kept, 6 and 7
  // dropped): 3 dropped, the first at line 4.
  TempDir dir;
  writeText(dir / "est.txt",
            "# t tx ty tz qx qy qz qw\n"
            "1.0 1 0 0 0 0 0 1\n"
            "2.0 2 0 0 0 0 0 1\n"
            "2.0 99 0 0 0 0 0 1\n"
            "4.000000000 4 0 0 0 0 0 1\n"
            "4.0 98 0 0 0 0 0 1\n"
            "4 97 0 0 0 0 0 1\n"
            "5.0 5 0 0 0 0 0 1\n");
  TrajectoryReadInfo info;
  const Trajectory t = readTrajectory((dir / "est.txt").string(), &info);
  EXPECT_EQ(info.format, TrajectoryFormat::kTum);
  EXPECT_EQ(info.duplicates_dropped, 3u);
  EXPECT_EQ(info.first_duplicate_line, 4);
  ASSERT_EQ(t.size(), 4u);
  const double x[] = {1, 2, 4, 5};
  for (size_t i = 0; i < t.size(); ++i) EXPECT_EQ(t[i].p_W_B.x(), x[i]) << i;
  EXPECT_EQ(t[2].t_ns, 4'000'000'000LL);
  // The plain API reads the same poses.
  TrajectoryFormat format;
  const Trajectory plain = readTrajectory((dir / "est.txt").string(), &format);
  ASSERT_EQ(plain.size(), 4u);
  EXPECT_EQ(plain[1].p_W_B.x(), 2.0);
  EXPECT_EQ(format, TrajectoryFormat::kTum);

  // EuRoC CSV ground truth with states, through both readers.
  writeText(dir / "gt.csv", std::string(kEurocHeader) +
                                "1000,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
                                "1000,7,7,7,1,0,0,0,9,9,9,0,0,0,0,0,0\n"
                                "2000,4,5,6,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  const auto states = readGroundTruthStates((dir / "gt.csv").string(), &info);
  EXPECT_EQ(info.format, TrajectoryFormat::kEurocCsv);
  EXPECT_EQ(info.duplicates_dropped, 1u);
  EXPECT_EQ(info.first_duplicate_line, 3);
  ASSERT_EQ(states.size(), 2u);
  EXPECT_EQ(states[0].pose.p_W_B.x(), 1.0);
  EXPECT_EQ(states[0].v_W.x(), 0.0);
  EXPECT_EQ(readGroundTruthStates((dir / "gt.csv").string()).size(), 2u);

  // A clean file reports nothing.
  writeText(dir / "clean.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n");
  readTrajectory((dir / "clean.txt").string(), &info);
  EXPECT_EQ(info.duplicates_dropped, 0u);
  EXPECT_EQ(info.first_duplicate_line, 0);
}

// ---- bad input: each error names the file, the line and the field --------------------------

TEST(TrajectoryIoErrors, MissingFile) {
  TempDir dir;
  std::string msg = expectError(dir / "nope.txt", 0, "cannot open");
  EXPECT_NE(msg.find("nope.txt"), std::string::npos);
}

TEST(TrajectoryIoErrors, EmptyFileAndOnlyComments) {
  TempDir dir;
  writeText(dir / "empty.txt", "");
  expectError(dir / "empty.txt", 0, "no poses");
  writeText(dir / "comments.csv", "# nothing\n\n#here\n");
  expectError(dir / "comments.csv", 0, "no poses");
  writeText(dir / "header_only.csv", "timestamp,px,py,pz,qw,qx,qy,qz\n");
  expectError(dir / "header_only.csv", 0, "no poses");
}

TEST(TrajectoryIoErrors, TruncatedLine) {
  TempDir dir;
  writeText(dir / "t.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0\n");
  expectError(dir / "t.txt", 2, "expected 8 fields, found 6");
  writeText(dir / "gt.csv", std::string(kEurocHeader) +
                                "1000,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
                                "2000,1,2,3,1,0,0,0,0,0,0,0\n");
  expectError(dir / "gt.csv", 3, "expected 8 (t,p,q) or 17");
  // A 17-column file cut right after the quaternion: 8 fields, but not what line 2 had.
  writeText(dir / "gt2.csv", std::string(kEurocHeader) +
                                 "1000,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
                                 "2000,1,2,3,1,0,0,0\n");
  expectError(dir / "gt2.csv", 3, "first data line has 17");
}

TEST(TrajectoryIoErrors, NonNumeric) {
  TempDir dir;
  writeText(dir / "t.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 abc 0 0 0 0 1\n");
  std::string msg = expectError(dir / "t.txt", 2, "not a number: 'abc'");
  EXPECT_NE(msg.find("field 'ty'"), std::string::npos) << msg;
  writeText(dir / "gt.csv", "1000,1,2,3,1,0,0,0\n20x0,1,2,3,1,0,0,0\n");
  msg = expectError(dir / "gt.csv", 2, "not an integer");
  EXPECT_NE(msg.find("field 'timestamp'"), std::string::npos) << msg;
  writeText(dir / "t2.txt", "1.0 0 0 0 0 0 0 1\n1.5x 0 0 0 0 0 0 1\n");
  expectError(dir / "t2.txt", 2, "not a number");
}

TEST(TrajectoryIoErrors, NanAndInf) {
  TempDir dir;
  writeText(dir / "t.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 nan 0 0 0 1\n");
  std::string msg = expectError(dir / "t.txt", 2, "not finite");
  EXPECT_NE(msg.find("field 'tz'"), std::string::npos) << msg;
  writeText(dir / "gt.csv", "1000,1,2,3,1,0,0,0\n2000,1,2,3,inf,0,0,0\n");
  msg = expectError(dir / "gt.csv", 2, "not finite");
  EXPECT_NE(msg.find("field 'q_w'"), std::string::npos) << msg;
}

TEST(TrajectoryIoErrors, NonMonotonicTimestamps) {
  TempDir dir;
  writeText(dir / "back.txt", "1.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n");
  std::string msg = expectError(dir / "back.txt", 3, "backwards");
  EXPECT_NE(msg.find("line 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("field 'timestamp'"), std::string::npos) << msg;
  // Backwards right after a dropped duplicate: located against the pose that was kept.
  writeText(dir / "dup_back.csv",
            "# header\n1000,1,2,3,1,0,0,0\n2000,1,2,3,1,0,0,0\n2000,1,2,3,1,0,0,0\n"
            "1500,1,2,3,1,0,0,0\n");
  msg = expectError(dir / "dup_back.csv", 5, "time goes backwards: 1500 ns after 2000 ns");
  EXPECT_NE(msg.find("at line 3"), std::string::npos) << msg;
}

TEST(TrajectoryIoErrors, BadQuaternion) {
  TempDir dir;
  writeText(dir / "t.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 0\n");
  std::string msg = expectError(dir / "t.txt", 2, "norm is 0");
  EXPECT_NE(msg.find("field 'quaternion'"), std::string::npos) << msg;
  writeText(dir / "gt.csv", "1000,1,2,3,0.9,0.1,0.1,0.1\n");
  expectError(dir / "gt.csv", 1, "norm is 0.916");
}

TEST(TrajectoryIoErrors, NanosecondsInTumFile) {
  TempDir dir;
  writeText(dir / "t.txt", "1403715273262142976 0 0 0 0 0 0 1\n");
  expectError(dir / "t.txt", 1, "out of range");
}

}  // namespace
}  // namespace adugs::data

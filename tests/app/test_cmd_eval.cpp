// `adugs eval` end to end: files written in a temp dir, the built binary run on them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "tests/test_support.h"

namespace adugs {
namespace {

using test::readFile;
using test::runAdugs;
using test::TempDir;
using test::writeText;

// A ground-truth loop in EuRoC CSV and an estimate in TUM whose positions are off by 0.1 m and
// 0.3 m alternately (no alignment: ATE RMSE = sqrt((0.01 + 0.09) / 2) = 0.2236068 m).
// `frame_change` moves the estimate into another world frame (then se3 alignment gives 0).
void writePair(const TempDir& dir, bool offsets, bool frame_change, int64_t est_time_shift_ns = 0) {
  std::string gt = "#timestamp [ns],p_x,p_y,p_z,q_w,q_x,q_y,q_z\n";
  std::string est = "# t tx ty tz qx qy qz qw\n";
  const double c = std::cos(0.3), s = std::sin(0.3);  // frame change: yaw 0.3 rad + shift
  for (int i = 0; i < 200; ++i) {
    const int64_t t_ns = 1403715273000000000LL + i * 50000000LL;
    const double a = 0.05 * i;
    const double x = 3 * std::cos(a), y = 2 * std::sin(a), z = 1 + 0.2 * std::sin(3 * a);
    char line[256];
    std::snprintf(line, sizeof(line), "%lld,%.12f,%.12f,%.12f,1,0,0,0\n",
                  static_cast<long long>(t_ns), x, y, z);
    gt += line;
    double ex = x, ey = y, ez = z;
    if (offsets) ez += (i % 2 ? 0.3 : 0.1);
    double qz = 0.0, qw = 1.0;
    if (frame_change) {
      ex = c * x - s * y + 5.0;
      ey = s * x + c * y - 2.0;
      qz = std::sin(0.15);
      qw = std::cos(0.15);
    }
    const int64_t te = t_ns + est_time_shift_ns + (i % 3 - 1) * 2000000;  // +-2 ms jitter
    std::snprintf(line, sizeof(line), "%lld.%09lld %.12f %.12f %.12f 0 0 %.12f %.12f\n",
                  static_cast<long long>(te / 1000000000LL),
                  static_cast<long long>(te % 1000000000LL), ex, ey, ez, qz, qw);
    est += line;
  }
  writeText(dir / "gt.csv", gt);
  writeText(dir / "est.txt", est);
}

std::string args(const TempDir& dir, const std::string& extra = "") {
  return "eval --est " + (dir / "est.txt").string() + " --gt " + (dir / "gt.csv").string() + " " +
         extra;
}

double printedAteRmse(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"(trans \[m\]\s+([0-9.]+))"))) return -1.0;
  return std::stod(m[1]);
}

TEST(CmdEval, PrintsKnownRmseWithoutAlignment) {
  TempDir dir;
  writePair(dir, true, false);
  std::string out;
  ASSERT_EQ(runAdugs(args(dir, "--align none"), &out), 0) << out;
  EXPECT_NEAR(printedAteRmse(out), 0.223607, 1e-6) << out;
  EXPECT_NE(out.find("200 pairs"), std::string::npos) << out;
  EXPECT_NE(out.find("(TUM, 200 poses)"), std::string::npos) << out;
  EXPECT_NE(out.find("(EuRoC CSV, 200 poses)"), std::string::npos) << out;
  EXPECT_NE(out.find("RPE"), std::string::npos) << out;
}

TEST(CmdEval, Se3AlignmentRemovesAFrameChange) {
  TempDir dir;
  writePair(dir, false, true);
  std::string out;
  ASSERT_EQ(runAdugs(args(dir), &out), 0) << out;  // se3 is the default
  EXPECT_NEAR(printedAteRmse(out), 0.0, 1e-6) << out;
  ASSERT_EQ(runAdugs(args(dir, "--align none"), &out), 0) << out;
  EXPECT_GT(printedAteRmse(out), 1.0) << out;
  ASSERT_EQ(runAdugs(args(dir, "--align posyaw --align-frames 20"), &out), 0) << out;
  EXPECT_NEAR(printedAteRmse(out), 0.0, 1e-6) << out;  // the change is a yaw + shift
  EXPECT_NE(out.find("the first 20 pairs"), std::string::npos) << out;
}

TEST(CmdEval, WritesPlotAndJson) {
  TempDir dir;
  writePair(dir, true, true);
  std::string out;
  const std::string plot = (dir / "eval.png").string(), json = (dir / "eval.json").string();
  ASSERT_EQ(
      runAdugs(args(dir, "--align sim3 --rpe-lengths 1,2.5 --plot " + plot + " --json " + json),
               &out),
      0)
      << out;
  const cv::Mat img = cv::imread(plot);
  ASSERT_FALSE(img.empty()) << out;
  EXPECT_EQ(img.cols, 1200);
  EXPECT_FALSE(std::filesystem::exists(plot + ".tmp"));
  std::ifstream in(json);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string j = ss.str();
  EXPECT_NE(j.find("\"mode\": \"sim3\""), std::string::npos) << j;
  EXPECT_NE(j.find("\"matched_pairs\": 200"), std::string::npos) << j;
  EXPECT_NE(j.find("\"length_m\": 2.5"), std::string::npos) << j;
  EXPECT_NE(out.find("    1.000 "), std::string::npos) << out;  // RPE rows for the given lengths
  EXPECT_NE(out.find("    2.500 "), std::string::npos) << out;
}

TEST(CmdEval, MissingFileIsNamed) {
  TempDir dir;
  writePair(dir, false, false);
  std::string out;
  const std::string missing = (dir / "nope.txt").string();
  EXPECT_NE(runAdugs("eval --est " + missing + " --gt " + (dir / "gt.csv").string(), &out), 0);
  EXPECT_NE(out.find(missing), std::string::npos) << out;
  EXPECT_NE(out.find("cannot open"), std::string::npos) << out;
}

TEST(CmdEval, BadLineIsLocated) {
  TempDir dir;
  writePair(dir, false, false);
  std::string gt;
  {
    std::ifstream in(dir / "gt.csv");
    std::stringstream ss;
    ss << in.rdbuf();
    gt = ss.str();
  }
  writeText(dir / "gt.csv",
            gt + "1403715283000000000,1,2,3,0.5,0,0,0\n");  // line 202: bad quaternion
  std::string out;
  EXPECT_NE(runAdugs(args(dir), &out), 0);
  EXPECT_NE(out.find((dir / "gt.csv").string() + ":202"), std::string::npos) << out;
  EXPECT_NE(out.find("quaternion"), std::string::npos) << out;
}

TEST(CmdEval, NoAssociatedPoses) {
  TempDir dir;
  writePair(dir, false, false, 25000000LL);  // est 25 +- 2 ms late, poses 50 ms apart
  std::string out;
  EXPECT_NE(runAdugs(args(dir), &out), 0);
  EXPECT_NE(out.find("no associated poses"), std::string::npos) << out;
  EXPECT_NE(out.find((dir / "est.txt").string()), std::string::npos) << out;
  // A larger --max-dt finds them.
  EXPECT_EQ(runAdugs(args(dir, "--max-dt 0.03"), &out), 0) << out;
}

// The "trans [m]" and "rot [deg]" rows of the ATE table.
std::string ateRows(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"((  trans \[m\].*\n  rot \[deg\].*\n))")))
    return "(no ATE table)";
  return m[1];
}

// Copies a trajectory file, repeating every `every`-th data line (from the 10th on) with the same
// timestamp and x = 123.5 m; returns how many lines it added.
int addDuplicates(const std::filesystem::path& in, const std::filesystem::path& out, char sep,
                  int every) {
  std::istringstream text(readFile(in));
  std::string line, result;
  int data_line = 0, added = 0;
  while (std::getline(text, line)) {
    result += line + "\n";
    if (line.empty() || line[0] == '#') continue;
    if (++data_line >= 10 && data_line % every == 0) {
      const size_t a = line.find(sep), b = line.find(sep, a + 1);
      result += line.substr(0, a + 1) + "123.5" + line.substr(b) + "\n";  // x = 123.5 m
      ++added;
    }
  }
  writeText(out, result);
  return added;
}

TEST(CmdEval, DuplicateTimestampsKeepTheFirstPoseWithAWarning) {
  // The estimate with 4 repeated stamps (their second pose 100 m away) evaluates exactly as the
  // file without them: the first pose of each stamp is used. Same for ground truth (EuRoC CSV).
  TempDir dir;
  writePair(dir, true, false);
  ASSERT_EQ(addDuplicates(dir / "est.txt", dir / "est_dup.txt", ' ', 50), 4);
  ASSERT_EQ(addDuplicates(dir / "gt.csv", dir / "gt_dup.csv", ',', 20), 10);
  const std::string dup = (dir / "est_dup.txt").string(), gt_dup = (dir / "gt_dup.csv").string();
  for (const std::string align : {"none", "se3", "sim3"}) {
    std::string clean, out;
    ASSERT_EQ(runAdugs(args(dir, "--align " + align), &clean), 0) << clean;
    ASSERT_EQ(runAdugs("eval --est " + dup + " --gt " + gt_dup + " --align " + align + " --json " +
                           (dir / "dup.json").string(),
                       &out),
              0)
        << out;
    EXPECT_EQ(ateRows(out), ateRows(clean)) << out;
    if (align == "none") {
      EXPECT_NEAR(printedAteRmse(out), 0.223607, 1e-6) << out;
    }
    EXPECT_NE(out.find("warning: " + dup +
                       ": 4 poses with the timestamp of the previous pose "
                       "dropped (first at line 52)"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("warning: " + gt_dup + ": 10 poses"), std::string::npos) << out;
    EXPECT_NE(out.find("(TUM, 200 poses, 4 duplicate stamps dropped)"), std::string::npos) << out;
    EXPECT_NE(out.find("200 pairs"), std::string::npos) << out;
    const std::string j = readFile(dir / "dup.json");
    EXPECT_NE(j.find("\"poses\": 200, \"duplicates_dropped\": 4}"), std::string::npos) << j;
    EXPECT_NE(j.find("\"poses\": 200, \"duplicates_dropped\": 10}"), std::string::npos) << j;
  }
  // Time going backwards is still refused, naming file and line.
  std::istringstream lines(readFile(dir / "est.txt"));
  std::string line, text, line2;
  for (int n = 1; std::getline(lines, line); ++n) {
    text += line + "\n";
    if (n == 2) line2 = line;
    if (n == 3) text += line2 + "\n";  // line 4 repeats line 2: earlier than line 3
  }
  writeText(dir / "est.txt", text);
  std::string out;
  EXPECT_NE(runAdugs(args(dir), &out), 0);
  EXPECT_NE(out.find((dir / "est.txt").string() + ":4"), std::string::npos) << out;
  EXPECT_NE(out.find("time goes backwards"), std::string::npos) << out;
}

// Ground truth and estimate in TUM at 10 Hz for 10 s (101 poses, same stamps): the estimate is
// 0.5 m off for poses 20..39 and turned by 40 deg for poses 60..69.
void writeCorrectRatePair(const TempDir& dir) {
  std::string gt = "# t tx ty tz qx qy qz qw\n", est = gt;
  const double half = 20.0 * std::acos(-1.0) / 180.0;  // a 40 deg turn about z
  const double qz = std::sin(half), qw = std::cos(half);
  for (int i = 0; i <= 100; ++i) {
    char line[256];
    const double x = 0.1 * i, y = std::sin(0.1 * i);
    const long long t_ms = 1403715273000LL + 100LL * i;
    std::snprintf(line, sizeof(line), "%lld.%03lld %.12f %.12f 1 0 0 0 1\n", t_ms / 1000,
                  t_ms % 1000, x, y);
    gt += line;
    const bool off = i >= 20 && i < 40, turned = i >= 60 && i < 70;
    std::snprintf(line, sizeof(line), "%lld.%03lld %.12f %.12f %.12f 0 0 %.12f %.12f\n",
                  t_ms / 1000, t_ms % 1000, x, y, off ? 1.5 : 1.0, turned ? qz : 0.0,
                  turned ? qw : 1.0);
    est += line;
  }
  writeText(dir / "gt.csv", gt);  // TUM content; the reader detects the format
  writeText(dir / "est.txt", est);
}

double printedCr(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"(\n  CR ([0-9.]+): correct)"))) return -1.0;
  return std::stod(m[1]);
}

TEST(CmdEval, OpenLorisCorrectRate) {
  // Defaults 1 m / 30 deg: the 10 turned poses are wrong; every other pose but the last (at the
  // end of the ground truth) counts its 0.1 s gap: 90 * 0.1 = 9 s of 10 s, CR 0.9.
  TempDir dir;
  writeCorrectRatePair(dir);
  std::string out;
  const std::string json = (dir / "eval.json").string();
  ASSERT_EQ(runAdugs(args(dir, "--align none --json " + json), &out), 0) << out;
  EXPECT_NEAR(printedCr(out), 0.9, 1e-9) << out;
  EXPECT_NE(out.find("correct 9.000 s of 10.000 s, 91 of 101 matched poses correct"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("position error <= 1 m and orientation error <= 30 deg"), std::string::npos)
      << out;
  const std::string j = readFile(json);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(j, m, std::regex(R"("correct_rate": \{"cr": ([0-9.e-]+))"))) << j;
  EXPECT_NEAR(std::stod(m[1]), 0.9, 1e-12) << j;
  EXPECT_NE(j.find("\"max_position_m\": 1, \"max_angle_deg\": 30"), std::string::npos) << j;
  // 0.4 m makes poses 20..39 wrong too (7 s); 45 deg accepts the turned ones (9 s + 1 s).
  ASSERT_EQ(runAdugs(args(dir, "--align none --cr-max-position-m 0.4"), &out), 0) << out;
  EXPECT_NEAR(printedCr(out), 0.7, 1e-9) << out;
  ASSERT_EQ(runAdugs(args(dir, "--align none --cr-max-angle-deg 45"), &out), 0) << out;
  EXPECT_NEAR(printedCr(out), 1.0, 1e-9) << out;
  EXPECT_NE(runAdugs(args(dir, "--cr-max-position-m -1"), &out), 0);
  EXPECT_NE(out.find("--cr-max-position-m"), std::string::npos) << out;
}

TEST(CmdEval, SkipFirstLeavesTheEstimatesFirstSecondsOut) {
  TempDir dir;
  writePair(dir, true, false);  // 200 poses 0.05 s apart, the first at -2 ms
  std::string out;
  ASSERT_EQ(runAdugs(args(dir, "--align none --skip-first 3"), &out), 0) << out;
  // From the first pose + 3 s on: poses 60..199 (the offsets alternate, so the RMSE stays).
  EXPECT_NE(out.find("140 pairs"), std::string::npos) << out;
  EXPECT_NE(out.find("(TUM, 200 poses)"), std::string::npos) << out;
  EXPECT_NE(out.find("skipped       the estimate's first 3 s (--skip-first): 140 of its poses evaluated"),
            std::string::npos)
      << out;
  EXPECT_NEAR(printedAteRmse(out), 0.223607, 1e-6) << out;
  EXPECT_NE(runAdugs(args(dir, "--skip-first 20"), &out), 0);  // the estimate spans 9.95 s
  EXPECT_NE(out.find("nothing left to evaluate"), std::string::npos) << out;
  EXPECT_NE(out.find("est.txt"), std::string::npos) << out;
  EXPECT_NE(runAdugs(args(dir, "--skip-first -1"), &out), 0);
  EXPECT_NE(out.find("--skip-first"), std::string::npos) << out;
}

TEST(CmdEval, BadOptions) {
  TempDir dir;
  writePair(dir, false, false);
  std::string out;
  EXPECT_NE(runAdugs(args(dir, "--align affine"), &out), 0);
  EXPECT_NE(out.find("--align"), std::string::npos) << out;
  EXPECT_NE(runAdugs(args(dir, "--max-dt -1"), &out), 0);
  EXPECT_NE(runAdugs(args(dir, "--rpe-lengths 1,-2"), &out), 0);
  EXPECT_NE(runAdugs("eval --gt " + (dir / "gt.csv").string(), &out), 0);
  EXPECT_NE(out.find("--est"), std::string::npos) << out;
  EXPECT_NE(runAdugs(args(dir, "--align sim3 --align-frames 2"), &out), 0);
  EXPECT_NE(out.find("at least 3"), std::string::npos) << out;
}

}  // namespace
}  // namespace adugs

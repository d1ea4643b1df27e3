// End-to-end: `adugs run` on the real EuRoC micro sequence and on bad input.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "data/formats/trajectory_io.h"
#include "tests/test_support.h"

namespace adugs::test {
namespace {

TEST(CmdRun, ImuOnlyBaselineOnRealEurocMicroWritesTrajectorySummaryAndPlot) {
  const auto seq = sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(seq);
  TempDir out;
  std::string log;
  const std::string gt = (seq / "groundtruth" / "V1_01_easy_vicon2gt.csv").string();
  ASSERT_EQ(runAdugs("run -q --estimator imu-only " + seq.string() + " --gt " + gt + " --out " +
                         out.path().string(),
                     &log),
            0)
      << log;
  const auto traj = data::readTrajectory((out / "trajectory.tum").string());
  EXPECT_EQ(traj.size(), 95u) << "one pose per frame";
  EXPECT_NE(log.find("ATE (se3)"), std::string::npos) << log;
  EXPECT_TRUE(std::filesystem::exists(out / "eval.png"));
  std::ifstream summary(out / "summary.yaml");
  std::string text((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("frames: 95"), std::string::npos) << text;
  EXPECT_NE(text.find("ate_se3_rmse_m:"), std::string::npos) << text;
  EXPECT_NE(text.find("correct_rate: "), std::string::npos) << text;  // OpenLORIS CR
  EXPECT_NE(log.find("  CR          "), std::string::npos) << log;
  // The first pose is the ground-truth state at the first frame (dead reckoning starts there).
  const auto gt_traj = data::readTrajectory(gt);
  EXPECT_LT((traj.front().p_W_B - gt_traj.front().p_W_B).norm(), 1e-3);
}

TEST(CmdRun, MissingSequenceFolderIsAnErrorNamingIt) {
  std::string log;
  EXPECT_EQ(runAdugs("run /nonexistent/sequence_xyz", &log), 2) << log;
  EXPECT_NE(log.find("/nonexistent/sequence_xyz"), std::string::npos) << log;
}

TEST(CmdRun, SequenceWithoutGroundTruthIsRefusedByTheImuOnlyBaseline) {
  const auto seq = sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(seq);
  TempDir out;
  std::string log;
  EXPECT_EQ(
      runAdugs("run -q --estimator imu-only " + seq.string() + " --out " + out.path().string(),
               &log),
      2)
      << log;
  EXPECT_NE(log.find("state_groundtruth_estimate0"), std::string::npos) << log;
}

}  // namespace
}  // namespace adugs::test

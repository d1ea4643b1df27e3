// The evaluation picture: drawn, encoded, written atomically, errors located.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "vio/eval/trajectory_plot.h"

namespace adugs::vio {
namespace {

EvalResult sampleEvaluation() {
  data::Trajectory gt, est;
  for (int i = 0; i < 300; ++i) {
    const double a = 0.03 * i;
    data::StampedPose p;
    p.t_ns = 5'000'000'000LL + i * 50'000'000LL;
    p.p_W_B = Eigen::Vector3d(4 * std::cos(a), 2 * std::sin(2 * a), 0.2 * std::sin(a));
    gt.push_back(p);
    p.p_W_B += Eigen::Vector3d(0.05 * std::sin(7 * a), 0.03 * std::cos(5 * a), 0.01 * i / 300.0);
    est.push_back(p);
  }
  EvalOptions options;
  options.align = AlignMode::kPosYaw;
  return evaluateTrajectory(est, gt, options);
}

TEST(TrajectoryPlot, RendersAPicture) {
  const cv::Mat img = renderEvalPlot(sampleEvaluation());
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, 1200);
  EXPECT_GT(img.rows, 800);
  // Not blank: the estimate's blue appears.
  int blue = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const cv::Vec3b& c = img.at<cv::Vec3b>(y, x);
      blue += c[0] > 150 && c[2] < 80;
    }
  EXPECT_GT(blue, 1000);
}

TEST(TrajectoryPlot, WritesADecodablePngAtomically) {
  adugs::test::TempDir dir;
  const std::string path = (dir / "eval.png").string();
  PlotOptions options;
  options.width_px = 900;
  options.title = "unit test";
  writeEvalPlot(path, sampleEvaluation(), options);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const cv::Mat back = cv::imread(path);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.cols, 900);
}

TEST(TrajectoryPlot, UnwritablePathIsAnInputError) {
  adugs::test::TempDir dir;
  const std::string path = (dir / "missing_dir" / "eval.png").string();
  try {
    writeEvalPlot(path, sampleEvaluation());
    FAIL() << "expected InputError";
  } catch (const data::InputError& e) {
    EXPECT_EQ(e.file(), path);
  }
  EXPECT_THROW(writeEvalPlot((dir / "eval.unknownext").string(), sampleEvaluation()), data::InputError);
}

}  // namespace
}  // namespace adugs::vio

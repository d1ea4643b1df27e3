#include "calib/target/chessboard.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/text_format.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(Chessboard, ParsesTheCommandLineSpec) {
  Chessboard b;
  ASSERT_TRUE(parseChessboardSpec("chessboard:9x6:0.025", b));
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  EXPECT_DOUBLE_EQ(b.square_m, 0.025);
  for (const char* bad : {"chessboard:9x6", "chessboard:9x6:0", "chessboard:1x6:0.02",
                          "chessboard:9x6:0.02mm", "checkerboard:9x6:0.02", "aprilgrid.yaml"})
    EXPECT_FALSE(parseChessboardSpec(bad, b)) << bad;
}

// OpenCV's sample chessboard images (opencv-doc), 9x6 inner corners, against the intrinsics
// OpenCV ships with them (left_intrinsics.yml: f = 535.9 with k3 and a fixed aspect ratio, so
// not exactly our model: 1 % on f, 2 px on the principal point).
TEST(Chessboard, CalibratesOpenCvsLeftImages) {
  const std::string dir = "/usr/share/doc/opencv-doc/examples/data/";
  if (!std::filesystem::exists(dir + "left01.jpg")) ADUGS_SKIP_OR_FAIL("opencv-doc not installed (" << dir << ")");
  const Chessboard board{9, 6, 0.025};
  std::vector<TargetObservation> views;
  for (int i = 1; i <= 14; ++i) {
    const cv::Mat gray = cv::imread(dir + strprintf("left%02d.jpg", i), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) continue;  // left10 is not shipped
    views.push_back(detectChessboard(board, gray, i));
    EXPECT_EQ(views.back().corners.size(), 54u) << i;
  }
  ASSERT_EQ(views.size(), 13u);
  const IntrinsicsResult r = calibrateIntrinsics(views, 640, 480, {});
  EXPECT_NEAR(r.camera.fu(), 535.916, 0.01 * 535.916);
  EXPECT_NEAR(r.camera.fv(), 535.916, 0.01 * 535.916);
  EXPECT_NEAR(r.camera.pu(), 342.283, 2.0);
  EXPECT_NEAR(r.camera.pv(), 235.571, 2.0);
  EXPECT_LT(r.rms_px, 0.3);
}

}  // namespace
}  // namespace adugs::calib

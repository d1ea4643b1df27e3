#include "calib/target/aprilgrid_render.h"

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/target/aprilgrid_detector.h"
#include "calib/target/tag36h11.h"
#include "calib/text_format.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(Tag36h11, BitsComeFromTheFamilyTable) {
  // Codes differ from each other, and the ids out of range throw.
  EXPECT_NE(tag36h11Bits(0), tag36h11Bits(1));
  EXPECT_THROW(tag36h11Bits(587), std::out_of_range);
  EXPECT_THROW(tag36h11Bits(-1), std::out_of_range);
  int white = 0;
  for (const auto& row : tag36h11Bits(0))
    for (bool b : row) white += b;
  EXPECT_GT(white, 5);
  EXPECT_LT(white, 31);
}

TEST(AprilGridRender, LayoutHasKalibrCornerSquaresAndExtent) {
  AprilGrid g;  // 6x6, 0.088, 0.3
  const TargetLayout layout = aprilGridLayout(g, 0.02);
  const double gap = 0.3 * 0.088;
  EXPECT_NEAR(layout.min_x, -gap - 0.02, 1e-12);
  EXPECT_NEAR(layout.max_x, 6 * g.pitch() + 0.02, 1e-12);  // last tag + its corner square
  int squares = 0;
  for (const Rect2d& r : layout.black)
    if (std::abs(r.x1 - r.x0 - gap) < 1e-12 && std::abs(r.y1 - r.y0 - gap) < 1e-12) ++squares;
  EXPECT_GE(squares, 7 * 7);
  EXPECT_FALSE(layout.caption.empty());
}

TEST(AprilGridRender, RasterHasTheTagBordersWhereTheGeometrySaysAndAPdf) {
  AprilGrid g;
  const RenderedTarget r = renderAprilGridPxPerM(g, 2000, 0.02);
  ASSERT_EQ(r.image.type(), CV_8UC1);
  // Inside the 2-bit border of tag 0, near corner 0: black. In the gap between tags: white.
  const Eigen::Vector2d in_border = r.pixelOf({0.005, 0.005, 0});
  EXPECT_EQ(r.image.at<uint8_t>(int(in_border.y()), int(in_border.x())), 0);
  const Eigen::Vector2d in_gap = r.pixelOf({0.088 + 0.013, 0.044, 0});
  EXPECT_EQ(r.image.at<uint8_t>(int(in_gap.y()), int(in_gap.x())), 255);
  // A corner square sits diagonally outside each tag corner.
  const Eigen::Vector2d in_square = r.pixelOf({-0.01, -0.01, 0});
  EXPECT_EQ(r.image.at<uint8_t>(int(in_square.y()), int(in_square.x())), 0);

  const std::string pdf = aprilGridPdf(aprilGridLayout(g, 0.02));
  EXPECT_EQ(pdf.rfind("%PDF-1.4", 0), 0u);
  // The xref offset must point at the xref table.
  const size_t sx = pdf.rfind("startxref\n");
  ASSERT_NE(sx, std::string::npos);
  const size_t xref = std::stoul(pdf.substr(sx + 10));
  EXPECT_EQ(pdf.compare(xref, 4, "xref"), 0);
  // True physical size: (6 * pitch + gap + 2 margins) in points.
  const double side_pt = (6 * g.pitch() + 0.3 * 0.088 + 0.04) * 72 / 0.0254;
  EXPECT_NE(pdf.find(strprintf("%.3f", side_pt)), std::string::npos);
}

// The PDF itself, rasterised by Ghostscript (when installed), is a detectable board with every
// corner where the geometry says.
TEST(AprilGridRender, GhostscriptRasterOfThePdfIsDetected) {
  if (!std::filesystem::exists("/usr/bin/gs")) ADUGS_SKIP_OR_FAIL("ghostscript not installed (/usr/bin/gs)");
  AprilGrid g;
  test::TempDir tmp("adugs_pdf");
  const std::string pdf = (tmp / "board.pdf").string(), png = (tmp / "board.png").string();
  writeAprilGridPdf(pdf, g, 0.02);
  const double dpi = 2500 * 0.0254;  // 2500 px/m
  const std::string cmd = "/usr/bin/gs -q -dNOPAUSE -dBATCH -dSAFER -sDEVICE=pnggray -r" +
                          strprintf("%.4f", dpi) + " -sOutputFile=" + png + " " + pdf;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  cv::Mat image = cv::imread(png, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  cv::GaussianBlur(image, image, cv::Size(0, 0), 1.5);
  const RenderedTarget ref = renderAprilGridPxPerM(g, 2500, 0.02);
  EXPECT_NEAR(image.cols, ref.image.cols, 1);
  AprilGridDetector detector(g);
  const TargetObservation obs = detector.detect(image);
  ASSERT_EQ(obs.corners.size(), 144u);
  for (const auto& c : obs.corners)
    EXPECT_LT((c.pixel - ref.pixelOf(c.point)).norm(), 1.0) << c.tag_id << "/" << c.corner;
}

}  // namespace
}  // namespace adugs::calib

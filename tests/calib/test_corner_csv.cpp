#include "calib/target/corner_csv.h"

#include <gtest/gtest.h>

#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(CornerCsv, ReadsTheEurocDetectionsAndTheirGrid) {
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "cam_april" / "cam0";
  ADUGS_REQUIRE_SHARED(dir);
  AprilGrid grid;
  grid.tag_rows = 1;
  const auto views = readCornerCsvs(dir.string(), nullptr, &grid);
  ASSERT_EQ(views.size(), 30u);
  EXPECT_EQ(grid.tag_rows, 6);
  EXPECT_DOUBLE_EQ(grid.tag_size_m, 0.088);
  EXPECT_EQ(views[0].t_ns, 1403709385487836928);
  EXPECT_EQ(views[0].corners.size(), 100u);
  EXPECT_EQ(views[0].corners[0].tag_id, 6);
  EXPECT_NEAR(views[0].corners[0].pixel.x(), 274.6642456055, 1e-9);
}

TEST(CornerCsv, RoundTripsAndChecksEveryRow) {
  test::TempDir tmp("adugs_corner_csv");
  AprilGrid g;
  TargetObservation obs;
  obs.t_ns = 123456789;
  obs.corners.push_back({7, 2, {10.25, 20.5}, g.corner(7, 2)});
  obs.corners.push_back({35, 3, {700.125, 400.0625}, g.corner(35, 3)});
  const std::string path = (tmp / "a.csv").string();
  writeCornerCsv(path, g, obs);
  const TargetObservation back = readCornerCsv(path, &g);
  ASSERT_EQ(back.corners.size(), 2u);
  EXPECT_EQ(back.t_ns, obs.t_ns);
  EXPECT_EQ(back.corners[1].tag_id, 35);
  EXPECT_DOUBLE_EQ(back.corners[1].pixel.x(), 700.125);

  const std::string header =
      "#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx\n";
  auto errorOf = [&](const std::string& row) -> std::string {
    test::writeText(tmp / "bad.csv", header + row);
    try {
      readCornerCsv((tmp / "bad.csv").string(), &g);
    } catch (const data::InputError& e) {
      return e.what();
    }
    return "";
  };
  // Wrong grid, tag outside it, point not matching the tag corner, short row.
  EXPECT_NE(errorOf("1,5,6,0.088,0.3,1,1,0,0,0,0,0\n").find("tag_rows"), std::string::npos);
  EXPECT_NE(errorOf("1,6,6,0.088,0.3,1,1,0,0,0,36,0\n").find("tag_id"), std::string::npos);
  EXPECT_NE(errorOf("1,6,6,0.088,0.3,1,1,0.5,0,0,0,0\n").find("p_x"), std::string::npos);
  EXPECT_NE(errorOf("1,6,6,0.088,0.3,1,1,0,0,0,0\n").find("bad.csv:2"), std::string::npos);
  EXPECT_THROW(readCornerCsvs((tmp / "missing").string(), nullptr), data::InputError);
}

}  // namespace
}  // namespace adugs::calib

#include "calib/target/aprilgrid.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "data/formats/csv_reader.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

TEST(AprilGrid, HandWorkedCornersOfKalibrLayout) {
  AprilGrid grid;  // 6x6, 0.088 m, spacing 0.3 -> pitch 0.1144 m
  EXPECT_NEAR(grid.pitch(), 0.1144, 1e-12);
  EXPECT_TRUE(grid.corner(0, 0).isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(grid.corner(0, 2).isApprox(Eigen::Vector3d(0.088, 0.088, 0)));
  // Tag 7 is row 1, column 1.
  EXPECT_TRUE(grid.corner(7, 1).isApprox(Eigen::Vector3d(0.2024, 0.1144, 0)));
  EXPECT_TRUE(grid.corner(35, 3).isApprox(Eigen::Vector3d(5 * 0.1144, 5 * 0.1144 + 0.088, 0)));
  EXPECT_THROW(grid.corner(36, 0), std::out_of_range);
  EXPECT_THROW(grid.corner(0, 4), std::out_of_range);
}

TEST(AprilGrid, ValidateRejectsBadFields) {
  AprilGrid g;
  g.tag_rows = 0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = AprilGrid{};
  g.tag_size_m = -1;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  EXPECT_NO_THROW(AprilGrid{}.validate());
}

// The real EuRoC detections list each corner with the 3-D point Kalibr assigned to it.
TEST(AprilGrid, MatchesThePointsOfRealEurocDetections) {
  const auto dir = test::sharedDataDir() / "euroc_calib_aprilgrid" / "cam_april" / "cam0";
  ADUGS_REQUIRE_SHARED(dir);
  AprilGrid grid;
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    data::CsvReader csv(entry.path().string());
    while (csv.next()) {
      csv.requireColumns(12);
      const int id = static_cast<int>(csv.int64At(10));
      const int corner = static_cast<int>(csv.int64At(11));
      Eigen::Vector3d p(csv.doubleAt(7), csv.doubleAt(8), csv.doubleAt(9));
      ASSERT_LT((grid.corner(id, corner) - p).norm(), 1e-6)
          << entry.path() << " line " << csv.lineNumber();
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace adugs::calib

#include "calib/target/aprilgrid_target_yaml.h"

#include <gtest/gtest.h>

#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

std::string errorOf(const std::string& text) {
  try {
    parseAprilGridYaml(text, "t.yaml");
  } catch (const data::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AprilGridTargetYaml, ReadsKalibrSpelling) {
  const AprilGrid g = parseAprilGridYaml(
      "target_type: 'aprilgrid'\ntagCols: 7\ntagRows: 5\ntagSize: 0.05\ntagSpacing: 0.25\n",
      "t.yaml");
  EXPECT_EQ(g.tag_rows, 5);
  EXPECT_EQ(g.tag_cols, 7);
  EXPECT_DOUBLE_EQ(g.tag_size_m, 0.05);
  EXPECT_DOUBLE_EQ(g.tag_spacing, 0.25);
  EXPECT_EQ(g.border_bits, 2);
}

TEST(AprilGridTargetYaml, ReadsTheRealEurocSnakeCaseFile) {
  const auto path = test::sharedDataDir() / "euroc_calib_aprilgrid" / "aprilgrid" / "target.yaml";
  ADUGS_REQUIRE_SHARED(path);
  const AprilGrid g = readAprilGridYaml(path.string());
  EXPECT_EQ(g.tag_rows, 6);
  EXPECT_EQ(g.tag_cols, 6);
  EXPECT_DOUBLE_EQ(g.tag_size_m, 0.088);
  EXPECT_DOUBLE_EQ(g.tag_spacing, 0.3);
}

TEST(AprilGridTargetYaml, FormatRoundTrips) {
  AprilGrid g;
  g.tag_rows = 4;
  g.tag_cols = 9;
  g.tag_size_m = 0.021;
  g.border_bits = 1;
  const std::string text = formatAprilGridYaml(g);
  EXPECT_NE(text.find("tagSize: 0.021 "), std::string::npos) << text;
  const AprilGrid back = parseAprilGridYaml(text, "round.yaml");
  EXPECT_EQ(back.tag_rows, 4);
  EXPECT_EQ(back.tag_cols, 9);
  EXPECT_EQ(back.tag_size_m, 0.021);
  EXPECT_EQ(back.border_bits, 1);
}

TEST(AprilGridTargetYaml, RejectsInconsistentFilesWithLocatedErrors) {
  const std::string ok = "target_type: aprilgrid\ntagRows: 6\ntagCols: 6\ntagSize: 0.088\n";
  // Missing key, named.
  EXPECT_NE(errorOf(ok).find("tagSpacing"), std::string::npos);
  // Unknown key, with its line.
  EXPECT_NE(errorOf(ok + "tagSpacing: 0.3\ncolor: red\n").find("t.yaml:6"), std::string::npos);
  // Both spellings of one key.
  EXPECT_NE(errorOf(ok + "tagSpacing: 0.3\ntag_spacing: 0.3\n").find("given twice"),
            std::string::npos);
  // Bad values.
  EXPECT_NE(errorOf("target_type: aprilgrid\ntagRows: 0\ntagCols: 6\ntagSize: 0.088\n"
                    "tagSpacing: 0.3\n")
                .find("tagRows"),
            std::string::npos);
  EXPECT_NE(errorOf("target_type: aprilgrid\ntagRows: 6\ntagCols: 6\ntagSize: -1\n"
                    "tagSpacing: 0.3\n")
                .find("tagSize"),
            std::string::npos);
  EXPECT_NE(errorOf("target_type: aprilgrid\ntagRows: 30\ntagCols: 30\ntagSize: 0.1\n"
                    "tagSpacing: 0.3\n")
                .find("587"),
            std::string::npos);
  // Other target types.
  EXPECT_NE(errorOf("target_type: 'checkerboard'\ntargetRows: 6\n").find("not supported"),
            std::string::npos);
  EXPECT_NE(errorOf("target_type: grid\n").find("unknown target type"), std::string::npos);
  EXPECT_THROW(readAprilGridYaml("/nonexistent/target.yaml"), data::InputError);
}

}  // namespace
}  // namespace adugs::calib

#include <gtest/gtest.h>

#include "data/formats/mot_io.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

TEST(MotIo, ReadsGroundTruthAndTrackerRows) {
  test::TempDir tmp("adugs_mot");
  test::writeText(tmp / "gt.txt",
                  "1,3,101,51,20,40,1,0,0.75\n"
                  "1,4,1,1,10,10,1,2,1.0\n"
                  "3,3,105,52,20,41,1,0,0.5\n");
  test::writeText(tmp / "res.txt", "2,7,11.5,21,30,60,0.9,-1,-1,-1\n");
  const auto gt = readMotFile((tmp / "gt.txt").string());
  ASSERT_EQ(gt.size(), 2u);
  ASSERT_EQ(gt.at(1).size(), 2u);
  const MotBox& b = gt.at(1)[0];
  EXPECT_EQ(b.id, 3);
  EXPECT_DOUBLE_EQ(b.left, 100);  // 1-based -> 0-based
  EXPECT_DOUBLE_EQ(b.centerX(), 110);
  EXPECT_DOUBLE_EQ(b.centerY(), 70);
  EXPECT_EQ(b.class_id, 0);
  EXPECT_DOUBLE_EQ(b.visibility, 0.75);
  EXPECT_EQ(gt.at(3)[0].height, 41);
  const auto res = readMotFile((tmp / "res.txt").string());
  EXPECT_EQ(res.at(2)[0].class_id, -1);
  EXPECT_DOUBLE_EQ(res.at(2)[0].visibility, 1.0);
  EXPECT_DOUBLE_EQ(res.at(2)[0].confidence, 0.9);
}

TEST(MotIo, BadRowsNameFileLineAndField) {
  test::TempDir tmp("adugs_mot_bad");
  const auto expectError = [&](const std::string& text, const std::string& field) {
    test::writeText(tmp / "bad.txt", text);
    try {
      readMotFile((tmp / "bad.txt").string());
      FAIL() << "no error for: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.txt"), std::string::npos) << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
    }
  };
  expectError("1,3,101,51,20,40,1,0,0.75\n1,3,101,51,-2,40,1,0,0.75\n", "bb_width");
  expectError("0,3,101,51,20,40,1,0,0.75\n", "frame");
  expectError("1,3,101,51,20,40,1,0,1.5\n", "visibility");
  expectError("1,3,101,51,20,nan,1,0,1\n", "bb_height");
  expectError("1,3,101,51\n", ":1");
  EXPECT_THROW(readMotFile((tmp / "missing.txt").string()), InputError);
}

}  // namespace
}  // namespace adugs::data

// CsvReader: comments, blank lines, line ends, separators, located conversion errors.
#include <optional>

#include <gtest/gtest.h>

#include "data/formats/csv_reader.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

using adugs::test::TempDir;
using adugs::test::writeText;

template <typename F>
std::optional<InputError> inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

std::string fileWith(const TempDir& dir, const std::string& text) {
  std::string path = (dir / "t.csv").string();
  writeText(path, text);
  return path;
}

TEST(CsvReader, SkipsCommentsAndBlankLinesAndKeepsLineNumbers) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "#timestamp,x\n\n1,2\n   \n# note\n3,4\n"));
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.lineNumber(), 3);
  EXPECT_EQ(csv.field(0), "1");
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.lineNumber(), 6);
  EXPECT_EQ(csv.int64At(0), 3);
  EXPECT_DOUBLE_EQ(csv.doubleAt(1), 4.0);
  EXPECT_FALSE(csv.next());
}

TEST(CsvReader, ReadsLastLineWithoutNewline) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "1,2\n5,6"));
  ASSERT_TRUE(csv.next());
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.int64At(0), 5);
  EXPECT_EQ(csv.int64At(1), 6);
  EXPECT_FALSE(csv.next());
}

TEST(CsvReader, HandlesCrLfByteOrderMarkAndSpacesAroundFields) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "\xEF\xBB\xBF#t,v\r\n 7 , 8.5 \r\n"));
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.lineNumber(), 2);
  EXPECT_EQ(csv.field(0), "7");
  EXPECT_EQ(csv.field(1), "8.5");
  EXPECT_DOUBLE_EQ(csv.doubleAt(1), 8.5);
}

TEST(CsvReader, WhitespaceModeSplitsOnRunsOfSpacesAndTabs) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "# t x y\n  1.5   2\t\t3  \n"), CsvReader::Separator::kWhitespace);
  ASSERT_TRUE(csv.next());
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_DOUBLE_EQ(csv.doubleAt(0), 1.5);
  EXPECT_EQ(csv.field(2), "3");
  EXPECT_FALSE(csv.next());
}

TEST(CsvReader, CommaModeKeepsEmptyFieldsAndRejectsThem) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "1,,3\n"));
  csv.setColumnNames({"a", "b", "c"});
  ASSERT_TRUE(csv.next());
  ASSERT_EQ(csv.size(), 3u);
  auto err = inputErrorOf([&] { csv.doubleAt(1); });
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "b");
  EXPECT_NE(std::string(err->what()).find("empty value"), std::string::npos);
}

TEST(CsvReader, MissingFileAndFolderNameThePath) {
  TempDir dir;
  std::string missing = (dir / "nope.csv").string();
  auto err = inputErrorOf([&] { CsvReader csv(missing); });
  ASSERT_TRUE(err);
  EXPECT_EQ(err->file(), missing);
  EXPECT_NE(std::string(err->what()).find(missing), std::string::npos);
  err = inputErrorOf([&] { CsvReader csv(dir.path().string()); });
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("folder"), std::string::npos);
}

TEST(CsvReader, WrongColumnCountNamesFileAndLine) {
  TempDir dir;
  std::string path = fileWith(dir, "#h\n1,2,3\n4,5\n");
  CsvReader csv(path);
  ASSERT_TRUE(csv.next());
  EXPECT_NO_THROW(csv.requireColumns(3));
  ASSERT_TRUE(csv.next());
  auto err = inputErrorOf([&] { csv.requireColumns(3); });
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 3);
  std::string msg = err->what();
  EXPECT_NE(msg.find(path + ":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 3 fields, found 2"), std::string::npos) << msg;
  EXPECT_NO_THROW(csv.requireColumns(2, 4));
}

TEST(CsvReader, NonNumericFieldNamesColumn) {
  TempDir dir;
  std::string path = fileWith(dir, "12x,1.0\n");
  CsvReader csv(path);
  csv.setColumnNames({"timestamp", "value"});
  ASSERT_TRUE(csv.next());
  auto err = inputErrorOf([&] { csv.int64At(0); });
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "timestamp");
  EXPECT_EQ(err->line(), 1);
  std::string msg = err->what();
  EXPECT_NE(msg.find("field 'timestamp'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'12x'"), std::string::npos) << msg;
  // Unnamed columns are numbered from 1.
  CsvReader unnamed(path);
  ASSERT_TRUE(unnamed.next());
  err = inputErrorOf([&] { unnamed.int64At(0); });
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field(), "column 1");
}

TEST(CsvReader, RejectsNonFiniteAndOutOfRangeNumbers) {
  TempDir dir;
  CsvReader csv(fileWith(dir, "nan,inf,-inf,1e400,99999999999999999999,1.5,+-2,0x10\n"));
  ASSERT_TRUE(csv.next());
  for (size_t i : {0u, 1u, 2u}) {
    auto err = inputErrorOf([&] { csv.doubleAt(i); });
    ASSERT_TRUE(err) << i;
    EXPECT_NE(std::string(err->what()).find("not finite"), std::string::npos) << err->what();
  }
  auto err = inputErrorOf([&] { csv.doubleAt(3); });
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("out of range"), std::string::npos) << err->what();
  err = inputErrorOf([&] { csv.int64At(4); });
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("out of range"), std::string::npos) << err->what();
  err = inputErrorOf([&] { csv.int64At(5); });  // "1.5" is not an integer
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("not an integer"), std::string::npos);
  EXPECT_TRUE(inputErrorOf([&] { csv.doubleAt(6); }));
  EXPECT_TRUE(inputErrorOf([&] { csv.int64At(7); }));
  err = inputErrorOf([&] { csv.field(8); });
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("missing"), std::string::npos);
}

TEST(CsvReader, StrictNumberParsing) {
  int64_t i = 0;
  double d = 0;
  bool overflow = false;
  EXPECT_TRUE(parseInt64("+42", i));
  EXPECT_EQ(i, 42);
  EXPECT_TRUE(parseInt64("-9223372036854775808", i));
  EXPECT_EQ(i, INT64_MIN);
  EXPECT_FALSE(parseInt64("9223372036854775808", i, &overflow));
  EXPECT_TRUE(overflow);
  EXPECT_FALSE(parseInt64("4 2", i, &overflow));
  EXPECT_FALSE(overflow);
  EXPECT_FALSE(parseInt64("", i));
  EXPECT_FALSE(parseInt64("+", i));
  EXPECT_TRUE(parseDouble("-1.25e-3", d));
  EXPECT_DOUBLE_EQ(d, -1.25e-3);
  EXPECT_TRUE(parseDouble("+.5", d));
  EXPECT_DOUBLE_EQ(d, 0.5);
  EXPECT_FALSE(parseDouble("1,5", d));
  EXPECT_FALSE(parseDouble("1.5 ", d));
}

}  // namespace
}  // namespace adugs::data

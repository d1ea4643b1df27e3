// YamlOptionsReader: strict options structs from YAML, with a small example struct.
#include <optional>

#include <gtest/gtest.h>

#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

// What a component's options look like: defaults in code, a nested struct.
struct ExampleOptions {
  int max_features = 150;
  double quality = 0.01;
  bool use_klt = true;
  int64_t timeout_ns = 5'000'000;
  std::string backend = "orb";
  std::vector<double> weights = {1.0, 2.0};
  struct Masker {
    int erode_px = 3;
    float score = 0.5f;
  } masker;
};

ExampleOptions loadExample(const std::string& text) {
  ExampleOptions o;
  YamlOptionsReader r = YamlOptionsReader::fromString(text, "example.yaml");
  r.optional("max_features", o.max_features, 1, 5000);
  r.optional("quality", o.quality, 0.0, 1.0);
  r.optional("use_klt", o.use_klt);
  r.optional("timeout_ns", o.timeout_ns);
  r.optional("backend", o.backend);
  r.optional("weights", o.weights);
  YamlOptionsReader m = r.child("masker");
  m.optional("erode_px", o.masker.erode_px, 0, 50);
  m.optional("score", o.masker.score);
  m.finish();
  r.finish();
  return o;
}

std::optional<InputError> errorOf(const std::string& text) {
  try {
    loadExample(text);
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

// Expects an InputError at `line` naming `field` and containing `words`.
void expectError(const std::string& text, long line, const std::string& field, const std::string& words) {
  auto err = errorOf(text);
  ASSERT_TRUE(err) << "no error for:\n" << text;
  EXPECT_EQ(err->file(), "example.yaml");
  EXPECT_EQ(err->line(), line) << err->what();
  EXPECT_EQ(err->field(), field) << err->what();
  std::string msg = err->what();
  EXPECT_NE(msg.find("example.yaml:" + std::to_string(line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find(words), std::string::npos) << msg;
}

TEST(ConfigYamlOptions, EmptyDocumentKeepsDefaults) {
  ExampleOptions o = loadExample("");
  EXPECT_EQ(o.max_features, 150);
  EXPECT_EQ(o.backend, "orb");
  EXPECT_EQ(o.masker.erode_px, 3);
  ExampleOptions c = loadExample("# only a comment\n");
  EXPECT_EQ(c.weights.size(), 2u);
}

TEST(ConfigYamlOptions, ReadsEveryTypeAndKeepsAbsentDefaults) {
  ExampleOptions o = loadExample(
      "%YAML:1.0\n"
      "max_features: 300\n"
      "use_klt: false\n"
      "timeout_ns: 1403715273262142976\n"
      "backend: \"yolo v4\"\n"
      "weights: [0.5, -1e-3, +2]\n"
      "masker:\n"
      "  score: 0.25\n");
  EXPECT_EQ(o.max_features, 300);
  EXPECT_DOUBLE_EQ(o.quality, 0.01);  // absent: default kept
  EXPECT_FALSE(o.use_klt);
  EXPECT_EQ(o.timeout_ns, 1403715273262142976);
  EXPECT_EQ(o.backend, "yolo v4");
  ASSERT_EQ(o.weights.size(), 3u);
  EXPECT_DOUBLE_EQ(o.weights[1], -1e-3);
  EXPECT_DOUBLE_EQ(o.weights[2], 2.0);
  EXPECT_EQ(o.masker.erode_px, 3);
  EXPECT_FLOAT_EQ(o.masker.score, 0.25f);
}

TEST(ConfigYamlOptions, UnknownKeyNamesKeyLineAndKnownKeys) {
  expectError("max_features: 10\nmax_feature: 20\n", 2, "max_feature", "unknown key");
  auto err = errorOf("max_feature: 20\n");
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("max_features"), std::string::npos) << err->what();
}

TEST(ConfigYamlOptions, UnknownNestedKeyNamesFullPath) {
  expectError("masker:\n  erode_px: 2\n  dilate_px: 9\n", 3, "masker.dilate_px", "unknown key");
}

TEST(ConfigYamlOptions, WrongTypesNameTheKey) {
  expectError("max_features: many\n", 1, "max_features", "expected an integer, found 'many'");
  expectError("\nmax_features: 3.0\n", 2, "max_features", "expected an integer");
  expectError("quality: [1, 2]\n", 1, "quality", "expected a number, found a list");
  expectError("use_klt: yes\n", 1, "use_klt", "expected true or false");
  expectError("backend:\n  a: 1\n", 1, "backend", "found a map");
  expectError("weights: 3\n", 1, "weights", "expected a list");
  expectError("masker: 3\n", 1, "masker", "expected a map");
  expectError("quality:\n", 1, "quality", "found no value");
}

TEST(ConfigYamlOptions, ListElementErrorsNameIndexAndLine) {
  expectError("weights:\n  - 1\n  - two\n", 3, "weights[1]", "expected a number, found 'two'");
}

TEST(ConfigYamlOptions, NonFiniteAndOutOfRangeValuesAreRejected) {
  expectError("quality: .nan\n", 1, "quality", "not finite");
  expectError("quality: -.inf\n", 1, "quality", "not finite");
  expectError("quality: 1e999\n", 1, "quality", "out of range");
  expectError("max_features: 0\n", 1, "max_features", "out of range [1, 5000]");
  expectError("max_features: 99999999999\n", 1, "max_features", "integer out of range");
  expectError("masker:\n  erode_px: 51\n", 2, "masker.erode_px", "out of range [0, 50]");
  expectError("masker:\n  score: 1e300\n", 2, "masker.score", "out of range for float");
}

TEST(ConfigYamlOptions, DuplicateAndNonScalarKeysAreErrors) {
  expectError("quality: 0.1\nuse_klt: true\nquality: 0.2\n", 3, "quality", "duplicate key (first on line 1)");
  auto err = errorOf("? [a, b]\n: 1\n");
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("plain name"), std::string::npos) << err->what();
}

TEST(ConfigYamlOptions, SyntaxErrorsAndNonMapDocumentsAreLocated) {
  auto err = errorOf("max_features: 10\nquality: [0.1\nuse_klt: true\n");
  ASSERT_TRUE(err);
  EXPECT_GT(err->line(), 1);
  EXPECT_NE(std::string(err->what()).find("YAML syntax error"), std::string::npos) << err->what();
  err = errorOf("- 1\n- 2\n");
  ASSERT_TRUE(err);
  EXPECT_NE(std::string(err->what()).find("expected a map"), std::string::npos) << err->what();
}

TEST(ConfigYamlOptions, SecondDocumentIsAnError) {
  auto err = errorOf("max_features: 10\n---\nquality: 0.5\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 2);  // the '---' line
  EXPECT_NE(std::string(err->what()).find("after the first YAML document"), std::string::npos) << err->what();
}

TEST(ConfigYamlOptions, StrayCommaIsAnErrorNotAHang) {
  // yaml-cpp 0.7's LoadAll never returns on this input (found by fuzz_yaml).
  auto err = errorOf(",");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 1);
  err = errorOf("quality: 0.5\n,\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 2);
}

TEST(ConfigYamlOptions, OpenCvHeaderKeepsLineNumbers) {
  expectError("%YAML:1.0\n# c\nbogus: 1\n", 3, "bogus", "unknown key");
}

TEST(ConfigYamlOptions, RequiredKeysAndChildren) {
  YamlOptionsReader r = YamlOptionsReader::fromString("a: 1\n", "req.yaml");
  int a = 0, b = 0;
  r.required("a", a);
  EXPECT_EQ(a, 1);
  try {
    r.required("b", b);
    FAIL() << "no error for a missing required key";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "b");
    EXPECT_NE(std::string(e.what()).find("missing required key"), std::string::npos);
  }
  EXPECT_THROW(r.child("sub", true), InputError);
  YamlOptionsReader absent = r.child("other");  // optional child: empty map
  int x = 7;
  EXPECT_FALSE(absent.optional("x", x));
  EXPECT_EQ(x, 7);
  EXPECT_NO_THROW(absent.finish());
  EXPECT_NO_THROW(r.finish());
}

TEST(ConfigYamlOptions, CheckAndFailNameTheKeyLine) {
  YamlOptionsReader r = YamlOptionsReader::fromString("a: 1\nb: -2\n", "chk.yaml");
  int b = 0;
  r.optional("b", b);
  try {
    r.check(b > 0, "b", "must be positive");
    FAIL() << "check did not throw";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_STREQ(e.what(), "chk.yaml:2: field 'b': must be positive");
  }
}

TEST(ConfigYamlOptions, FromFileNamesMissingFileAndReadsExisting) {
  adugs::test::TempDir dir;
  std::string path = (dir / "opts.yaml").string();
  try {
    YamlOptionsReader::fromFile(path);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
  }
  adugs::test::writeText(path, "%YAML:1.0\nq: 2.5\n");
  YamlOptionsReader r = YamlOptionsReader::fromFile(path);
  double q = 0;
  EXPECT_TRUE(r.optional("q", q));
  EXPECT_DOUBLE_EQ(q, 2.5);
  r.finish();
}

}  // namespace
}  // namespace adugs::data

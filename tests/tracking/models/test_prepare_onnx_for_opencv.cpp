// scripts/prepare_onnx_for_opencv.py run for real on torch.onnx exports (opsets 12 and 13) of a
// tiny model with the graph patterns that keep OpenCV 4.6 dnn from running ultralytics' YOLOv8 /
// YOLO11 exports (tests/tracking/models/make_ultralytics_like_onnx_export.py documents which
// construct fails how; ultralytics itself is not a Debian package, so CI cannot make real exports).
// Unprepared, the project's loader rejects them with the hint to run the script; prepared, OpenCV
// reproduces the TorchScript output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <opencv2/dnn.hpp>
#include <string>
#include <vector>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "tracking/detect/detector_factory.h"
#include "tracking/detect/ultralytics_onnx_detector.h"

namespace adugs::tracking {
namespace {

namespace fs = std::filesystem;

constexpr int kInputHeight = 128, kInputWidth = 160;
constexpr int kRows = 4 + 3;                        // box + person, car, chair
constexpr int kAnchors = 16 * 20 + 8 * 10 + 4 * 5;  // strides 8, 16, 32
const std::vector<std::string> kExports = {"export_opset12.onnx", "export_opset13.onnx"};

// Generated once per test process (torch export of both opsets plus the reference: ~2 s).
const fs::path& ultralyticsLikeExports() { return test::pythonGenerated("tests/tracking/models/make_ultralytics_like_onnx_export.py"); }

#define REQUIRE_EXPORTS()                            \
  const fs::path exports = ultralyticsLikeExports(); \
  if (exports.empty()) FAIL() << "no exports"

std::string readFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A raw float32 file as a blob of the given shape.
cv::Mat readBlob(const fs::path& file, std::vector<int> dims) {
  cv::Mat blob(static_cast<int>(dims.size()), dims.data(), CV_32F);
  const std::string bytes = readFile(file);
  EXPECT_EQ(bytes.size(), blob.total() * sizeof(float)) << file;
  if (bytes.size() == blob.total() * sizeof(float))
    std::copy(bytes.begin(), bytes.end(), blob.ptr<char>());
  return blob;
}

struct ScriptResult {
  int exit_code = -1;
  std::string err;  // stderr only: the script's messages are there, its summary on stdout
};

ScriptResult prepareOnnx(const fs::path& in, const fs::path& out, const test::TempDir& tmp) {
  const fs::path err = tmp / "stderr.txt";
  const std::string command = std::string("/usr/bin/python3 ") + ADUGS_SOURCE_DIR +
                              "/scripts/prepare_onnx_for_opencv.py '" + in.string() + "' '" +
                              out.string() + "' >/dev/null 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  ScriptResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = readFile(err);
  return r;
}

void expectModelRefused(const std::string& path, const std::vector<std::string>& fragments) {
  try {
    makeDetector(path);
    ADD_FAILURE() << "no data::InputError thrown for " << path;
  } catch (const data::InputError& e) {
    for (const std::string& s : fragments)
      EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what() << "\nlacks: " << s;
  }
}

TEST(PrepareOnnxForOpencv, UnpreparedExportsAreRejectedWithTheHint) {
  REQUIRE_EXPORTS();
  // Both opsets fail in OpenCV 4.6's importer at the first problem, the Identity nodes torch makes
  // of the equal box biases (the later ones are checked in the generator's header).
  for (const std::string& name : kExports) {
    SCOPED_TRACE(name);
    const std::string path = (exports / name).string();
    expectModelRefused(path, {path, "Identity", "scripts/prepare_onnx_for_opencv.py"});
  }
}

TEST(PrepareOnnxForOpencv, PreparedExportsMatchTorchScript) {
  REQUIRE_EXPORTS();
  const cv::Mat input = readBlob(exports / "input.f32", {1, 3, kInputHeight, kInputWidth});
  const cv::Mat reference = readBlob(exports / "output.f32", {1, kRows, kAnchors});
  // The comparison means something only if the model's scores are not near-constant.
  const cv::Mat ref_rows(kRows, kAnchors, CV_32F, const_cast<float*>(reference.ptr<float>()));
  double low = 0, high = 0;
  cv::minMaxLoc(ref_rows.rowRange(4, kRows), &low, &high);
  EXPECT_LT(low, 0.05);
  EXPECT_GT(high, 0.95);

  test::TempDir tmp("adugs_prepared_onnx");
  for (const std::string& name : kExports) {
    SCOPED_TRACE(name);
    const fs::path prepared = tmp / ("prepared_" + name);
    const ScriptResult r = prepareOnnx(exports / name, prepared, tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;

    cv::dnn::Net net = cv::dnn::readNetFromONNX(prepared.string());
    net.setInput(input);
    const cv::Mat out = net.forward();
    ASSERT_EQ(out.dims, 3);
    ASSERT_EQ(out.size[1], kRows);
    ASSERT_EQ(out.size[2], kAnchors);
    const cv::Mat out_rows(kRows, kAnchors, CV_32F, const_cast<float*>(out.ptr<float>()));
    const double max_diff = cv::norm(out_rows, ref_rows, cv::NORM_INF);
    EXPECT_LT(max_diff, 1e-3) << "boxes in input pixels, scores 0..1";
    RecordProperty("max_abs_diff_" + name, std::to_string(max_diff));

    // The project's loader takes it, with the input size from the export's metadata.
    const std::unique_ptr<Detector> detector = makeDetector(prepared.string());
    const auto* onnx = dynamic_cast<const UltralyticsOnnxDetector*>(detector.get());
    ASSERT_NE(onnx, nullptr);
    EXPECT_EQ(onnx->info().input_size, cv::Size(kInputWidth, kInputHeight));
    EXPECT_EQ(onnx->info().names, (std::vector<std::string>{"person", "car", "chair"}));
  }
}

TEST(PrepareOnnxForOpencv, BadInputsExitWith2AndNameTheFile) {
  REQUIRE_EXPORTS();
  test::TempDir tmp("adugs_prepare_bad");
  const fs::path out = tmp / "out.onnx";

  const fs::path missing = tmp / "yolo11n.onnx";
  ScriptResult r = prepareOnnx(missing, out, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not found"), std::string::npos) << r.err;

  // An interrupted download: the protobuf ends inside the weights.
  const std::string whole = readFile(exports / "export_opset13.onnx");
  const fs::path truncated = tmp / "truncated.onnx";
  test::writeText(truncated, whole.substr(0, whole.size() / 2));
  r = prepareOnnx(truncated, out, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(truncated.string()), std::string::npos) << r.err;

  const fs::path empty = tmp / "empty.onnx";
  test::writeText(empty, "");
  r = prepareOnnx(empty, out, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(empty.string()), std::string::npos) << r.err;

  EXPECT_FALSE(fs::exists(out)) << "nothing is written for a bad input";
}

}  // namespace
}  // namespace adugs::tracking

// The ultralytics YOLO11 / YOLOv8 backends (TorchScript through libtorch, ONNX through OpenCV
// dnn), the centred letterbox and the 1 x (4 + C) x N decoding, on tiny models of the exports'
// interface whose output is known in closed form
// (tests/tracking/models/make_ultralytics_like_models.py documents them: a person box whose score
// is the red value of the input's centre pixel, a car box scored by its blue value, an
// overlapping person for NMS, a non-dynamic class).
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "tracking/detect/detector_factory.h"
#include "tracking/detect/letterbox.h"
#include "tracking/detect/onnx_signature.h"
#include "tracking/detect/torchscript_detector.h"
#include "tracking/detect/ultralytics_output.h"

namespace adugs::tracking {
namespace {

namespace fs = std::filesystem;

const fs::path& ultralyticsLikeModels() { return test::pythonGenerated("tests/tracking/models/make_ultralytics_like_models.py"); }

#define REQUIRE_MODELS()                            \
  const fs::path models = ultralyticsLikeModels(); \
  if (models.empty()) FAIL() << "no models"

using test::expectInputError;

void expectBox(const Box& b, double cx, double cy, double w, double h) {
  EXPECT_NEAR(b.cx, cx, 1e-3);
  EXPECT_NEAR(b.cy, cy, 1e-3);
  EXPECT_NEAR(b.w, w, 1e-3);
  EXPECT_NEAR(b.h, h, 1e-3);
}

TEST(Letterbox, CentredPaddingAsUltralyticsRoundsIt) {
  // 300 x 200 into 256 x 192: r = min(256/300, 192/200) = 0.85333; resized 256 x round(170.67) =
  // 171; dh = 10.5 -> top = round(10.4) = 10 (bottom gets 11).
  cv::Mat image(200, 300, CV_8UC3, cv::Scalar(0, 0, 255));
  const Letterbox lb = letterbox(image, {256, 192}, LetterboxPlacement::kCentred);
  EXPECT_NEAR(lb.scale, 256.0 / 300, 1e-12);
  EXPECT_EQ(lb.offset, cv::Point2d(0, 10));
  ASSERT_EQ(lb.image.size(), cv::Size(256, 192));
  EXPECT_EQ(lb.image.at<cv::Vec3b>(9, 100), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(lb.image.at<cv::Vec3b>(10, 100), cv::Vec3b(0, 0, 255));
  EXPECT_EQ(lb.image.at<cv::Vec3b>(180, 100), cv::Vec3b(0, 0, 255));
  EXPECT_EQ(lb.image.at<cv::Vec3b>(181, 100), cv::Vec3b(114, 114, 114));
  // Input (128, 96) is the image centre (150, 100): (128 - 0) / r, (96 - 10) / r.
  expectBox(lb.toImage({128, 96, 25.6, 8.5333}), 150, 100.78125, 30, 10);
}

TEST(Letterbox, TopLeftAsYoloxTruncatesAndDoesNotOffset) {
  // 640 x 480 into 416 x 416: r = 0.65, resized 416 x 312 at the top-left.
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(7));
  const Letterbox lb = letterbox(grey, {416, 416}, LetterboxPlacement::kTopLeft);
  EXPECT_EQ(lb.offset, cv::Point2d(0, 0));
  EXPECT_EQ(lb.image.type(), CV_8UC3);
  EXPECT_EQ(lb.image.at<cv::Vec3b>(311, 415), cv::Vec3b(7, 7, 7));
  EXPECT_EQ(lb.image.at<cv::Vec3b>(312, 0), cv::Vec3b(114, 114, 114));
  expectBox(lb.toImage({65, 130, 13, 26}), 100, 200, 20, 40);
}

TEST(UltralyticsOutput, MetadataAsTheExportersWriteIt) {
  // ONNX metadata_props hold Python literals; config.txt JSON gives string keys.
  const UltralyticsModelInfo onnx = parseUltralyticsMetadata(
      {{"imgsz", "[192, 256]"}, {"names", "{0: 'person', 1: 'bicycle', 2: \"it's\"}"}, {"task", "detect"}}, "m.onnx");
  EXPECT_EQ(onnx.input_size, cv::Size(256, 192));  // [height, width]
  EXPECT_EQ(onnx.names, (std::vector<std::string>{"person", "bicycle", "it's"}));
  EXPECT_EQ(onnx.task, "detect");
  const UltralyticsModelInfo json =
      parseUltralyticsMetadata({{"imgsz", "640"}, {"names", "{\"1\": \"car\", \"0\": \"person\"}"}}, "m");
  EXPECT_EQ(json.input_size, cv::Size(640, 640));
  EXPECT_EQ(json.names, (std::vector<std::string>{"person", "car"}));
  EXPECT_TRUE(parseUltralyticsMetadata({}, "m").names.empty());
  expectInputError([] { parseUltralyticsMetadata({{"imgsz", "[-3, 640]"}}, "bad.onnx"); },
                   {"bad.onnx", "imgsz", "not positive"});
  expectInputError([] { parseUltralyticsMetadata({{"names", "{0: 'a', 5: 'b'}"}}, "bad.onnx"); },
                   {"bad.onnx", "names", "class ids are not 0..1"});
  expectInputError([] { parseUltralyticsMetadata({{"names", "{0: [unclosed"}}, "bad.onnx"); }, {"bad.onnx", "names"});
}

TEST(UltralyticsOutput, ClassCountFromTheNamesOrTheRows) {
  UltralyticsModelInfo info;
  EXPECT_EQ(ultralyticsClassCount(84, info, "m"), 80);
  info.names.assign(80, "x");
  EXPECT_EQ(ultralyticsClassCount(84, info, "m"), 80);
  info.task = "segment";
  EXPECT_EQ(ultralyticsClassCount(116, info, "m"), 80);
  info.names.assign(3, "x");
  expectInputError([&] { ultralyticsClassCount(116, info, "m.torchscript"); },
                   {"m.torchscript", "names 3 classes", "should have 39 rows, but it has 116"});
}

TEST(UltralyticsOutput, HandWorkedColumns) {
  // 3 classes (person, bicycle, chair = not dynamic when names are given), 4 anchors; the
  // image was scaled by 0.5 and placed 10 px down.
  cv::Mat out = cv::Mat::zeros(4 + 3, 4, CV_32F);
  const float person[] = {50, 60, 20, 40, 0.9f, 0.1f, 0};
  const float chair[] = {80, 80, 10, 10, 0, 0, 0.99f};
  const float weak[] = {10, 20, 4, 4, 0.2f, 0, 0};
  for (int r = 0; r < 7; ++r) {
    out.at<float>(r, 1) = person[r];
    out.at<float>(r, 2) = chair[r];
    out.at<float>(r, 3) = weak[r];
  }
  Letterbox lb;
  lb.scale = 0.5;
  lb.offset = {0, 10};
  DetectorOptions options;
  options.keep_classes = dynamicClassIds({"person", "bicycle", "chair"});
  EXPECT_EQ(options.keep_classes, (std::set<int>{0, 1}));
  // Names without a dynamic class (a custom model): every class is kept rather than none.
  UltralyticsModelInfo custom;
  custom.names = {"forklift", "pallet"};
  EXPECT_EQ(keptClasses(custom, {0}, "m"), (std::set<int>{0, 1}));
  EXPECT_EQ(keptClasses(UltralyticsModelInfo{}, {7}, "m"), (std::set<int>{7}));
  const std::vector<Detection> d = decodeUltralyticsOutput(out, 3, lb, options);
  ASSERT_EQ(d.size(), 1u);
  expectBox(d[0].box, 100, 100, 40, 80);
  EXPECT_EQ(d[0].class_id, 0);
  EXPECT_NEAR(d[0].score, 0.9, 1e-6);
}

// The closed-form model on a 400 x 400 image: r = 0.48, left padding 32.
//   person (100, 80, 40, 60) in the input -> ((100 - 32) / 0.48, 80 / 0.48, 40 / 0.48, 60 / 0.48)
//   car (200, 100, 50, 30) -> (350, 208.333, 104.167, 62.5)
void expectClosedFormDetections(Detector& detector) {
  const cv::Mat red(400, 400, CV_8UC3, cv::Scalar(0, 0, 255));
  std::vector<Detection> d = detector.detect(red);
  ASSERT_EQ(d.size(), 1u) << "the overlapping person must be suppressed, the table dropped";
  EXPECT_EQ(d[0].class_id, 0);
  EXPECT_NEAR(d[0].score, 1.0, 1e-5);  // red / 255: RGB order and scaling as ultralytics'
  expectBox(d[0].box, 141.6667, 166.6667, 83.3333, 125);
  const cv::Mat blue(400, 400, CV_8UC3, cv::Scalar(255, 0, 0));
  d = detector.detect(blue);
  ASSERT_EQ(d.size(), 2u);  // the car, and the second person (0.5) now that the first scores 0
  EXPECT_EQ(d[0].class_id, 2);
  expectBox(d[0].box, 350, 208.3333, 104.1667, 62.5);
  EXPECT_EQ(d[1].class_id, 0);
  EXPECT_NEAR(d[1].score, 0.5, 1e-6);
  expectBox(d[1].box, 145.8333, 168.75, 83.3333, 125);
  const cv::Mat grey(400, 400, CV_8UC1, cv::Scalar(255));
  d = detector.detect(grey);  // white: person 1.0 and car 1.0
  ASSERT_EQ(d.size(), 2u);
}

TEST(TorchScriptDetector, DecodesTheExportWithItsConfigMetadata) {
  REQUIRE_MODELS();
  TorchScriptDetector detector((models / "detect.torchscript").string());
  EXPECT_EQ(detector.info().input_size, cv::Size(256, 192));
  EXPECT_EQ(detector.info().names.size(), 80u);
  EXPECT_EQ(detector.info().names[2], "car");
  expectClosedFormDetections(detector);
}

TEST(TorchScriptDetector, SegmentationExportsGiveTheirBoxes) {
  REQUIRE_MODELS();
  TorchScriptDetector detector((models / "segment.torchscript").string());
  EXPECT_EQ(detector.info().task, "segment");
  expectClosedFormDetections(detector);
}

TEST(TorchScriptDetector, BadFilesAreNamedWithWhatIsWrong) {
  REQUIRE_MODELS();
  test::TempDir tmp("adugs_torchscript_bad");
  const std::string missing = (tmp / "yolo11n.torchscript").string();
  expectInputError([&] { TorchScriptDetector d(missing); }, {missing, "not found"});
  test::writeText(tmp / "text.torchscript", "not a model\n");
  expectInputError([&] { TorchScriptDetector d((tmp / "text.torchscript").string()); },
                   {"text.torchscript", "cannot load it as a TorchScript archive"});
  const std::string mismatch = (models / "names_mismatch.torchscript").string();
  expectInputError([&] { TorchScriptDetector d(mismatch); }, {mismatch, "names 3 classes", "it has 84"});
  const std::string two = (models / "two_inputs.torchscript").string();
  expectInputError([&] { TorchScriptDetector d(two); }, {two, "expected forward(images)", "forward(images, scale)"});
  // A SAM-like or other module with an image input but another output.
  const std::string onnx_as_ts = (tmp / "detect.torchscript").string();
  fs::copy_file(models / "detect.onnx", onnx_as_ts);
  expectInputError([&] { TorchScriptDetector d(onnx_as_ts); }, {onnx_as_ts, "TorchScript"});
}

TEST(UltralyticsOnnxDetector, TheFactoryTellsTheLayoutsApartAndDecodesLikeTorchScript) {
  REQUIRE_MODELS();
  const OnnxSignature sig = readOnnxSignature((models / "detect.onnx").string());
  EXPECT_EQ(sig.metadata.at("task"), "detect");
  EXPECT_EQ(sig.metadata.at("imgsz"), "[192, 256]");
  EXPECT_EQ(describeShape(sig.outputs.front()), "[1, 84, 1008]");
  for (const char* name : {"detect.onnx", "detect_no_metadata.onnx", "detect.torchscript"}) {
    SCOPED_TRACE(name);
    const std::unique_ptr<Detector> detector = makeDetector((models / name).string());
    expectClosedFormDetections(*detector);
  }
}

TEST(DetectorFactory, TorchBackendsArePresentInThisBuild) {
  // scripts/setup.sh installs libtorch-dev; a build without it would silently lose the paper's
  // detector and MobileSAM, so the test build insists.
  EXPECT_TRUE(haveTorchBackends());
}

}  // namespace
}  // namespace adugs::tracking

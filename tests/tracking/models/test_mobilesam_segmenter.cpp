// MobileSAM weights are not available on the build machines, so these tests drive the real
// MobileSamSegmenter code path (libtorch loading, interface checks, SAM pre-processing, box
// prompt, post-processing) with tiny TorchScript modules of the interface of
// scripts/export_mobilesam.py whose output is known in closed form:
// tests/tracking/models/make_sam_like_torchscript.py documents them. (The export script itself
// was run on the real MobileSAM architecture: doc/results.md.)
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "data/input_error.h"
#include "tests/test_support.h"
#include "tracking/segment/mobilesam_segmenter.h"
#include "tracking/segment/sam_transforms.h"
#include "tracking/segment/segmenter_factory.h"

namespace adugs::tracking {
namespace {

namespace fs = std::filesystem;

constexpr int kHeight = 480, kWidth = 640;

// Writes the SAM-like modules once per test run; an empty path after a FAIL.
const fs::path& samLikeModels() { return test::pythonGenerated("tests/tracking/models/make_sam_like_torchscript.py"); }

#define REQUIRE_MODELS()                   \
  const fs::path models = samLikeModels(); \
  if (models.empty()) FAIL() << "no models"

// A black scene with red rectangles (objects) and prompt boxes, all scaled by s. Edges are
// multiples of 10 px at s = 1 (of 5 px at s = 0.5), i.e. 16 px in the 1024 frame: the encoder's
// 16 x 16 pooling cells then hold pure object or pure background.
struct Scene {
  cv::Mat image;
  std::vector<cv::Rect> objects;
  std::vector<Box> boxes;
};

Scene makeScene(double s) {
  Scene scene;
  scene.image =
      cv::Mat::zeros(static_cast<int>(kHeight * s), static_cast<int>(kWidth * s), CV_8UC3);
  const auto rect = [s](int x0, int y0, int x1, int y1) {
    return cv::Rect(cv::Point(static_cast<int>(x0 * s), static_cast<int>(y0 * s)),
                    cv::Point(static_cast<int>(x1 * s), static_cast<int>(y1 * s)));
  };
  scene.objects = {rect(200, 100, 360, 300), rect(500, 320, 600, 440)};
  for (const cv::Rect& r : scene.objects) scene.image(r).setTo(cv::Scalar(0, 0, 255));  // BGR red
  scene.boxes = {
      Box::fromCorners(150 * s, 150 * s, 300 * s, 400 * s),  // cuts through object 0
      Box::fromCorners(400 * s, 30 * s, 480 * s, 250 * s),   // background only
      Box::fromCorners(470 * s, 290 * s, 630 * s, 520 * s),  // holds object 1, leaves the image
  };
  return scene;
}

// What the SAM-like decoder predicts: inside a box AND on a red object; a box with no object
// pixel falls back to the whole (clipped) box. Also returns the pixels within `band` px of any
// box or object edge, where bilinear interpolation blurs the logit's zero crossing.
cv::Mat expectedMask(const Scene& scene, int band, cv::Mat* near_edges) {
  cv::Mat objects = cv::Mat::zeros(scene.image.size(), CV_8UC1);
  for (const cv::Rect& r : scene.objects) objects(r).setTo(255);
  cv::Mat expected = cv::Mat::zeros(scene.image.size(), CV_8UC1);
  *near_edges = cv::Mat::zeros(scene.image.size(), CV_8UC1);
  for (const Box& b : scene.boxes) {
    const cv::Rect r = clippedRect(b, scene.image.cols, scene.image.rows);
    cv::Mat object = objects(r).clone();
    if (cv::countNonZero(object) == 0) object.setTo(255);
    cv::Mat target = expected(r);
    cv::bitwise_or(target, object, target);
    cv::rectangle(*near_edges, r, cv::Scalar(255), 2 * band + 1);
  }
  for (const cv::Rect& r : scene.objects)
    cv::rectangle(*near_edges, r, cv::Scalar(255), 2 * band + 1);
  return expected;
}

int mismatchesAwayFromEdges(const cv::Mat& mask, const Scene& scene, int band) {
  cv::Mat near_edges;
  const cv::Mat expected = expectedMask(scene, band, &near_edges);
  cv::Mat diff = mask != expected;
  diff.setTo(0, near_edges);
  return cv::countNonZero(diff);
}

TEST(SamTransforms, ResizeLongestSideAndBoxPromptByHand) {
  EXPECT_EQ(samResizedSize({640, 480}), cv::Size(1024, 768));
  EXPECT_EQ(samResizedSize({480, 640}), cv::Size(768, 1024));
  // 1024 / 333 * 200 = 615.02 -> 615 (SAM rounds with floor(x + 0.5)).
  EXPECT_EQ(samResizedSize({333, 200}), cv::Size(1024, 615));
  // x * 1024/640 = 1.6 x, y * 768/480 = 1.6 y.
  const cv::Vec4f c = samBoxPrompt(Box::fromCorners(100, 80, 300, 260), {640, 480});
  EXPECT_FLOAT_EQ(c[0], 160);
  EXPECT_FLOAT_EQ(c[1], 128);
  EXPECT_FLOAT_EQ(c[2], 480);
  EXPECT_FLOAT_EQ(c[3], 416);
}

float blobAt(const cv::Mat& blob, int c, int y, int x) {
  const int index[] = {0, c, y, x};
  return blob.at<float>(index);
}

TEST(SamTransforms, EncoderInputIsNormalisedRgbPaddedBottomRight) {
  const cv::Mat red(48, 64, CV_8UC3, cv::Scalar(0, 0, 255));  // BGR
  const cv::Mat blob = samEncoderInput(red);
  ASSERT_EQ(blob.dims, 4);
  EXPECT_EQ(blob.size[1], 3);
  EXPECT_EQ(blob.size[2], 1024);
  // Channel 0 is R: (255 - 123.675) / 58.395; channel 2 is B: (0 - 103.53) / 57.375.
  EXPECT_NEAR(blobAt(blob, 0, 10, 10), 2.24891, 1e-4);
  EXPECT_NEAR(blobAt(blob, 1, 10, 10), -116.28 / 57.12, 1e-4);
  EXPECT_NEAR(blobAt(blob, 2, 767, 1023), -1.80444, 1e-4);
  // The image fills rows [0, 768); rows below are zero padding.
  EXPECT_EQ(blobAt(blob, 0, 768, 10), 0.0f);
  EXPECT_EQ(blobAt(blob, 2, 1023, 1023), 0.0f);
}

TEST(SamTransforms, LowResMaskIsCroppedToTheResizedImageBeforeUpscaling) {
  // Positive above low-res row 96 = 1024-frame row 384 = image row 384 / 1.6 = 240 of 480.
  // Without the crop to 768 rows it would end at row 96 * 4 * 480 / 1024 = 180.
  cv::Mat low_res(256, 256, CV_32F, cv::Scalar(-1));
  low_res.rowRange(0, 96).setTo(1);
  const cv::Mat logits = samUpscaleLowResMask(low_res, {640, 480});
  ASSERT_EQ(logits.size(), cv::Size(640, 480));
  EXPECT_GT(logits.at<float>(236, 100), 0);
  EXPECT_LT(logits.at<float>(244, 100), 0);
}

TEST(MobileSamSegmenter, SegmentsBoxTimesObjectFromTheLowResolutionLogits) {
  REQUIRE_MODELS();
  MobileSamSegmenter sam((models / "encoder.pt").string(), (models / "decoder.pt").string());
  const Scene scene = makeScene(1.0);
  const cv::Mat mask = sam.segment(scene.image, scene.boxes);
  ASSERT_EQ(mask.size(), scene.image.size());
  ASSERT_EQ(mask.type(), CV_8UC1);
  EXPECT_EQ(mismatchesAwayFromEdges(mask, scene, 3), 0);
  EXPECT_EQ(sam.lastFallbacks(), 1);  // the background-only box
  // Object 1 is all of box 2's mask: the box corners around it are not masked.
  EXPECT_EQ(mask.at<uchar>(300, 480), 0);
  EXPECT_EQ(mask.at<uchar>(380, 550), 255);
  EXPECT_EQ(cv::countNonZero(sam.segment(scene.image, {})), 0);
}

TEST(MobileSamSegmenter, OtherImageSizesMapThroughTheResizedFrame) {
  REQUIRE_MODELS();
  MobileSamSegmenter sam((models / "encoder.pt").string(), (models / "decoder.pt").string());
  const Scene scene = makeScene(0.5);  // 320 x 240: resized x 3.2 into the 1024 frame
  const cv::Mat mask = sam.segment(scene.image, scene.boxes);
  ASSERT_EQ(mask.size(), scene.image.size());
  EXPECT_EQ(mismatchesAwayFromEdges(mask, scene, 2), 0);
  EXPECT_EQ(sam.lastFallbacks(), 1);
}

TEST(MobileSamSegmenter, GreyImagesAreAccepted) {
  REQUIRE_MODELS();
  MobileSamSegmenter sam((models / "encoder.pt").string(), (models / "decoder.pt").string());
  // A white square in a grey image: R = 255 inside, 0 outside, so box times square again.
  cv::Mat grey = cv::Mat::zeros(kHeight, kWidth, CV_8UC1);
  grey(cv::Rect(200, 100, 160, 200)).setTo(255);
  const cv::Mat mask = sam.segment(grey, {Box::fromCorners(150, 150, 300, 400)});
  EXPECT_EQ(mask.at<uchar>(200, 250), 255);
  EXPECT_EQ(mask.at<uchar>(200, 170), 0);  // in the box, off the square
  EXPECT_EQ(mask.at<uchar>(350, 250), 0);
}

using test::expectInputError;

TEST(MobileSamSegmenter, BadModelFilesGiveErrorsNamingTheFile) {
  REQUIRE_MODELS();
  const std::string encoder = (models / "encoder.pt").string();
  const std::string decoder = (models / "decoder.pt").string();
  test::TempDir dir;
  const std::string missing = (dir / "no_such_encoder.pt").string();
  expectInputError([&] { MobileSamSegmenter s(missing, decoder); }, {missing, "not found"});
  const std::string text = (dir / "notes.pt").string();
  test::writeText(text, "this is a text file, not a TorchScript archive\n");
  expectInputError([&] { MobileSamSegmenter s(text, decoder); }, {text, "cannot load it as a TorchScript"});
  expectInputError([&] { MobileSamSegmenter s(encoder, text); }, {text, "cannot load it as a TorchScript"});
  const std::string empty = (dir / "empty.pt").string();
  test::writeText(empty, "");
  expectInputError([&] { MobileSamSegmenter s(encoder, empty); }, {empty, "TorchScript"});
  // Truncated archives: an error naming the file, never a crash.
  std::ifstream whole(decoder, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(whole)), {});
  const std::string truncated = (dir / "truncated.pt").string();
  for (size_t length : {size_t{1}, size_t{40}, bytes.size() / 2, bytes.size() - 3}) {
    std::ofstream(truncated, std::ios::binary).write(bytes.data(), length);
    expectInputError([&] { MobileSamSegmenter s(encoder, truncated); }, {truncated});
  }
  const std::string two_inputs = (models / "decoder_two_inputs.pt").string();
  expectInputError([&] { MobileSamSegmenter s(encoder, two_inputs); },
                   {two_inputs, "forward(image_embeddings, point_coords, point_labels)",
                    "the module has forward(image_embeddings, point_coords)"});
  const std::string wrong_shape = (models / "decoder_wrong_shape.pt").string();
  expectInputError([&] { MobileSamSegmenter s(encoder, wrong_shape); },
                   {wrong_shape, "low_res_masks [1, 1, 256, 256]", "[1, 1, 128, 128]"});
  // Files swapped: each is checked against its role.
  expectInputError([&] { MobileSamSegmenter s(decoder, encoder); }, {decoder, "forward(image)"});
  // The encoder's output is checked on its first (expensive) run.
  MobileSamSegmenter small((models / "encoder_wrong_shape.pt").string(), decoder);
  const Scene scene = makeScene(1.0);
  expectInputError([&] { small.segment(scene.image, scene.boxes); },
                   {"encoder_wrong_shape.pt", "[1, 256, 64, 64]", "[1, 256, 32, 32]"});
}

TEST(SegmenterFactory, BuildsEachKindAndRejectsBadRequests) {
  EXPECT_STREQ(makeBoxSegmenter()->name(), "grabcut");
  EXPECT_STREQ(makeBoxSegmenter("grabcut")->name(), "grabcut");
  EXPECT_STREQ(makeBoxSegmenter("box")->name(), "box");
  GrabCutOptions too_small;  // the run config's options reach GrabCut, which checks them
  too_small.max_side = 8;
  EXPECT_THROW(makeBoxSegmenter("grabcut", "", "", too_small), std::invalid_argument);
  EXPECT_THROW(makeBoxSegmenter("mobilesam"), std::invalid_argument);
  EXPECT_THROW(makeBoxSegmenter("mobilesam", "enc.pt", ""), std::invalid_argument);
  EXPECT_THROW(makeBoxSegmenter("sam2"), std::invalid_argument);
  EXPECT_THROW(makeBoxSegmenter("mobilesam", "/nonexistent/enc.pt", "/nonexistent/dec.pt"), data::InputError);
  REQUIRE_MODELS();
  const auto sam = makeBoxSegmenter("mobilesam", (models / "encoder.pt").string(), (models / "decoder.pt").string());
  EXPECT_STREQ(sam->name(), "mobilesam");
}

}  // namespace
}  // namespace adugs::tracking

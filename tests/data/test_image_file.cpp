// data/formats/image_file: PNG and JPEG through libpng/libjpeg must give the pixels cv::imread gives
// (the oracle: OpenCV's imgcodecs, linked into the tests only), on real files of every kind the
// machine has: EuRoC's camera frames, and opencv-doc's sample images (grey, RGB, RGBA, palette
// PNGs; baseline and progressive, grey and colour JPEGs).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include <zlib.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "data/formats/image_file.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;
using test::TempDir;

const fs::path kOpenCvSamples = "/usr/share/doc/opencv-doc/examples/data";

using test::samePixels;

std::string describe(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows) + " type " + std::to_string(m.type());
}

std::vector<fs::path> filesWithExtension(const fs::path& dir, const std::vector<std::string>& exts) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (std::find(exts.begin(), exts.end(), ext) != exts.end() && fs::file_size(e.path()) < 3'000'000)
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void expectAsOpenCv(const fs::path& file) {
  for (const auto& [mode, flags] : {std::pair{ImageRead::kGrey, cv::IMREAD_GRAYSCALE},
                                    std::pair{ImageRead::kUnchanged, cv::IMREAD_UNCHANGED}}) {
    const cv::Mat expected = cv::imread(file.string(), flags);
    ASSERT_FALSE(expected.empty()) << file;
    const cv::Mat ours = readImageFile(file.string(), mode);
    EXPECT_TRUE(samePixels(ours, expected))
        << file << " mode " << flags << ": ours " << describe(ours) << ", OpenCV " << describe(expected);
  }
}

TEST(ImageFile, EurocFramesAsOpenCvReadsThem) {
  const fs::path dir = test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data";
  ADUGS_REQUIRE_SHARED(dir);
  const std::vector<fs::path> files = filesWithExtension(dir, {".png"});
  ASSERT_GE(files.size(), 20u);
  for (size_t i = 0; i < files.size(); i += 5) expectAsOpenCv(files[i]);
}

TEST(ImageFile, OpenCvSamplePngsAndJpegsAsOpenCvReadsThem) {
  if (!fs::is_directory(kOpenCvSamples)) ADUGS_SKIP_OR_FAIL("opencv-doc is not installed: " << kOpenCvSamples);
  const std::vector<fs::path> files = filesWithExtension(kOpenCvSamples, {".png", ".jpg"});
  ASSERT_GE(files.size(), 60u);
  // What the samples cover, so that the comparison below is known to reach each decoder branch.
  int palette = 0, rgba = 0, grey_jpeg = 0, colour_jpeg = 0;
  for (const fs::path& f : files) {
    const cv::Mat unchanged = cv::imread(f.string(), cv::IMREAD_UNCHANGED);
    if (f.extension() == ".jpg") (unchanged.channels() == 1 ? grey_jpeg : colour_jpeg)++;
    if (f.extension() == ".png" && unchanged.channels() == 4) ++rgba;
    std::ifstream in(f, std::ios::binary);
    std::string head(32, '\0');
    in.read(head.data(), 32);
    if (f.extension() == ".png" && head[25] == 3) ++palette;  // IHDR colour type 3
    expectAsOpenCv(f);
  }
  EXPECT_GE(palette, 1);
  EXPECT_GE(rgba, 3);
  EXPECT_GE(grey_jpeg, 3);
  EXPECT_GE(colour_jpeg, 3);
}

// What OpenCV writes and cv::imread reads, in every depth and channel count adugs handles.
TEST(ImageFile, SixteenBitAndAlphaPngsAsOpenCvReadsThem) {
  TempDir tmp;
  cv::RNG rng(7);
  for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3, CV_8UC4, CV_16UC4}) {
    cv::Mat image(37, 53, type);
    rng.fill(image, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
    const fs::path file = tmp / ("t" + std::to_string(type) + ".png");
    ASSERT_TRUE(cv::imwrite(file.string(), image));
    expectAsOpenCv(file);
    EXPECT_TRUE(samePixels(readImageFile(file.string(), ImageRead::kUnchanged), image)) << type;
  }
}

TEST(ImageFile, WrittenPngsReadBackExactlyByOpenCv) {
  TempDir tmp;
  cv::RNG rng(11);
  for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_8UC4, CV_16UC3}) {
    cv::Mat image(41, 29, type);
    rng.fill(image, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
    const fs::path file = tmp / "out.png";
    writeImageFile(file.string(), image);
    EXPECT_FALSE(fs::exists(tmp / "out.png.tmp"));
    EXPECT_TRUE(samePixels(cv::imread(file.string(), cv::IMREAD_UNCHANGED), image)) << type;
  }
}

TEST(ImageFile, WrittenJpegIsWhatOpenCvWrites) {
  const fs::path source = kOpenCvSamples / "baboon.jpg";
  if (!fs::exists(source)) ADUGS_SKIP_OR_FAIL("opencv-doc is not installed: " << source);
  const cv::Mat bgr = cv::imread(source.string(), cv::IMREAD_COLOR);
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  for (const cv::Mat& image : {bgr, grey}) {
    std::vector<uchar> expected;
    ASSERT_TRUE(cv::imencode(".jpg", image, expected));
    const std::vector<uint8_t> ours = encodeImage(".jpg", image, "test.jpg");
    // Same library, same quality (95) and defaults: the same file.
    EXPECT_EQ(ours.size(), expected.size());
    EXPECT_TRUE(std::equal(ours.begin(), ours.end(), expected.begin(), expected.end()));
    std::string why;
    EXPECT_TRUE(samePixels(decodeImage(ours, ImageRead::kUnchanged, &why), cv::imdecode(expected, cv::IMREAD_UNCHANGED)))
        << why;
  }
}

// Formats other than PNG and JPEG go through OpenCV in libadugs_media.so.
TEST(ImageFile, OtherFormatsGoThroughTheMediaModule) {
  TempDir tmp;
  cv::Mat image(20, 30, CV_8UC3);
  cv::randu(image, 0, 256);
  for (const std::string ext : {".bmp", ".pgm", ".tif"}) {
    cv::Mat written = image;
    if (ext == ".pgm") cv::cvtColor(image, written, cv::COLOR_BGR2GRAY);
    const fs::path file = tmp / ("x" + ext);
    writeImageFile(file.string(), written);
    EXPECT_TRUE(samePixels(cv::imread(file.string(), cv::IMREAD_UNCHANGED), written)) << ext;
    EXPECT_TRUE(samePixels(readImageFile(file.string(), ImageRead::kUnchanged), written)) << ext;
  }
}

std::string errorOf(const std::string& path, ImageRead mode = ImageRead::kGrey) {
  try {
    readImageFile(path, mode);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  }
  ADD_FAILURE() << path << " was read";
  return "";
}

TEST(ImageFile, BadFilesAreInputErrorsNamingTheFileAndWhy) {
  const fs::path dir = test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data";
  ADUGS_REQUIRE_SHARED(dir);
  const fs::path real = filesWithExtension(dir, {".png"}).front();
  const std::string bytes = test::readFile(real);
  TempDir tmp;
  EXPECT_NE(errorOf((tmp / "missing.png").string()).find("no such image file"), std::string::npos);
  test::writeText(tmp / "empty.png", "");
  EXPECT_NE(errorOf((tmp / "empty.png").string()).find("empty image file"), std::string::npos);
  // A real frame cut in half: libpng stops at the missing data.
  test::writeText(tmp / "half.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_NE(errorOf((tmp / "half.png").string()).find("truncated"), std::string::npos);
  // One flipped byte inside the image data: the chunk's CRC no longer matches.
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x5a);
  test::writeText(tmp / "flipped.png", flipped);
  EXPECT_NE(errorOf((tmp / "flipped.png").string()).find("not a readable PNG"), std::string::npos);
  // A header asking for 30000 x 30000 pixels (its CRC recomputed: a valid header): refused
  // before anything is allocated.
  std::string huge = bytes;
  for (const int at : {16, 20}) {
    const uint32_t side = 30000;
    for (int k = 0; k < 4; ++k) huge[at + k] = static_cast<char>((side >> (24 - 8 * k)) & 0xff);
  }
  const uint32_t crc = static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(huge.data() + 12), 17));
  for (int k = 0; k < 4; ++k) huge[29 + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
  test::writeText(tmp / "huge.png", huge);
  EXPECT_NE(errorOf((tmp / "huge.png").string()).find("larger than 512 MB"), std::string::npos);
  test::writeText(tmp / "text.png", "this is not an image at all\n");
  EXPECT_NE(errorOf((tmp / "text.png").string()).find("neither PNG nor JPEG"), std::string::npos);
  std::string why;
  EXPECT_TRUE(decodeImage(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 100), ImageRead::kGrey, &why).empty());
  EXPECT_NE(why.find("truncated"), std::string::npos) << why;
  // A JPEG cut short: libjpeg would pad it with grey and carry on.
  const fs::path jpeg = kOpenCvSamples / "baboon.jpg";
  if (!fs::exists(jpeg)) ADUGS_SKIP_OR_FAIL(jpeg << " missing: run scripts/setup.sh (package opencv-doc)");
  const std::string j = test::readFile(jpeg);
  test::writeText(tmp / "half.jpg", j.substr(0, j.size() / 2));
  EXPECT_NE(errorOf((tmp / "half.jpg").string(), ImageRead::kUnchanged).find("truncated"), std::string::npos);
}

// A chunk whose length field says 1.8 GB in a file of 60 bytes (what the image fuzzer found):
// libpng allocates a text chunk whole from that field before reading it, so the decoder must
// skip such chunks instead. Decoded in a child process, whose peak virtual size starts at its
// current size at the fork: the allocation would raise it by 1.8 GB even if never touched.
TEST(ImageFile, ACorruptChunkLengthIsNotAllocated) {
  const std::vector<uint8_t> small = encodeImage(".png", cv::Mat(16, 16, CV_8UC1, cv::Scalar(7)), "test");
  std::vector<uint8_t> bytes(small.begin(), small.begin() + 33);  // signature + IHDR chunk
  const uint8_t chunk[] = {0x70, 0x00, 0x00, 0x00, 'i', 'T', 'X', 't', 'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 0, 0, 0, 0};
  bytes.insert(bytes.end(), std::begin(chunk), std::end(chunk));
  TempDir tmp;
  const fs::path file = tmp / "corrupt_length.png";
  test::writeText(file, std::string(bytes.begin(), bytes.end()));
  // The same chunk layout with an honest length decodes: text chunks are skipped, not refused.
  std::vector<uint8_t> honest(small.begin(), small.begin() + 33);
  const std::string text = "Comment\0\0\0\0\0made by the test";
  const uint32_t n = static_cast<uint32_t>(text.size());
  std::string body = "iTXt" + text;
  const uint32_t crc = static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size())));
  const auto bigEndian = [&honest](uint32_t v) {
    for (int k = 0; k < 4; ++k) honest.push_back(static_cast<uint8_t>(v >> (24 - 8 * k)));
  };
  bigEndian(n);
  honest.insert(honest.end(), body.begin(), body.end());
  bigEndian(crc);
  honest.insert(honest.end(), small.begin() + 33, small.end());
  std::string why;
  const cv::Mat decoded = decodeImage(honest, ImageRead::kGrey, &why);
  ASSERT_EQ(decoded.size(), cv::Size(16, 16)) << why;
  EXPECT_EQ(decoded.at<uint8_t>(5, 5), 7);

  const auto peakVirtualKb = [] {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("VmPeak:", 0) == 0) return std::stol(line.substr(7));
    return -1L;
  };
  test::AdugsProcess child(
      [&] {
        const long before = peakVirtualKb();
        std::string message;
        try {
          readImageFile(file.string(), ImageRead::kGrey);
        } catch (const InputError& e) {
          message = e.what();
        }
        const long grown_mb = (peakVirtualKb() - before) / 1024;
        std::cerr << "error: '" << message << "', peak virtual size grew by " << grown_mb << " MB\n";
        if (before < 0) return 3;
        if (grown_mb >= 256) return 4;
        return message.find("truncated") != std::string::npos ? 0 : 1;
      },
      tmp / "child.log");
  EXPECT_EQ(child.wait(std::chrono::seconds(120)), 0)
      << "1: not refused as truncated, 3: no VmPeak, 4: the chunk's length was allocated; the child said: "
      << test::readFile(tmp / "child.log");
}

TEST(ImageFile, UnwritableImagesAreInputErrors) {
  TempDir tmp;
  const cv::Mat floats(4, 4, CV_32FC1, cv::Scalar(0.5));
  EXPECT_THROW(writeImageFile((tmp / "f.png").string(), floats), InputError);
  EXPECT_THROW(writeImageFile((tmp / "e.png").string(), cv::Mat()), InputError);
  EXPECT_THROW(writeImageFile((tmp / "no_such_dir/x.png").string(), cv::Mat(4, 4, CV_8UC1, cv::Scalar(1))), InputError);
  EXPECT_FALSE(fs::exists(tmp / "f.png"));
}

}  // namespace
}  // namespace adugs::data

// data/formats/grey_png: grey PNGs decoded with libdeflate must give what cv::imread gives, for
// every row filter the PNG spec has (libpng writes each one on request), both bit depths and
// both read modes, and for the real EuRoC frames; everything else must be left to libpng.
#include <gtest/gtest.h>

#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "data/formats/grey_png.h"
#include "data/formats/image_file.h"
#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

using test::samePixels;

// Writes a CV_8UC1/CV_16UC1/CV_8UC3 image with libpng, every row with `filter` (a PNG_FILTER_*
// mask), at zlib `level`, interlaced or not.
void writeWithLibpng(const fs::path& path, const cv::Mat& image, int filter, int level, bool interlaced) {
  FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr) << path;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  const int depth = image.depth() == CV_16U ? 16 : 8;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), depth,
               image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE,
               PNG_FILTER_TYPE_BASE);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, filter);
  png_set_compression_level(png, level);
  png_text text{};
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = const_cast<char*>("Comment");
  text.text = const_cast<char*>("an ancillary chunk, skipped");
  png_set_text(png, info, &text, 1);
  png_write_info(png, info);
  if (depth == 16) png_set_swap(png);  // cv::Mat holds little-endian samples
  std::vector<png_bytep> rows(static_cast<size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) rows[static_cast<size_t>(y)] = const_cast<png_bytep>(image.ptr<uint8_t>(y));
  png_write_image(png, rows.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

std::vector<uint8_t> bytesOf(const fs::path& path) {
  const std::string s = test::readFile(path);
  return std::vector<uint8_t>(s.begin(), s.end());
}

// A grey 8-bit PNG built by hand around the given filtered rows (each led by its filter byte).
std::vector<uint8_t> pngAround(int width, int height, const std::vector<uint8_t>& rows, bool damage_stream) {
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const auto put32 = [&png](uint32_t v) {
    for (int k = 0; k < 4; ++k) png.push_back(static_cast<uint8_t>(v >> (24 - 8 * k)));
  };
  const auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
    put32(static_cast<uint32_t>(data.size()));
    std::vector<uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    png.insert(png.end(), body.begin(), body.end());
    put32(static_cast<uint32_t>(crc32(0, body.data(), static_cast<uInt>(body.size()))));
  };
  std::vector<uint8_t> ihdr(13, 0);
  for (int k = 0; k < 4; ++k) {
    ihdr[static_cast<size_t>(k)] = static_cast<uint8_t>(width >> (24 - 8 * k));
    ihdr[static_cast<size_t>(4 + k)] = static_cast<uint8_t>(height >> (24 - 8 * k));
  }
  ihdr[8] = 8;  // depth; colour type, compression, filter method, interlace all 0
  chunk("IHDR", ihdr);
  uLongf size = compressBound(static_cast<uLong>(rows.size()));
  std::vector<uint8_t> stream(size);
  compress2(stream.data(), &size, rows.data(), static_cast<uLong>(rows.size()), 6);
  stream.resize(size);
  if (damage_stream) stream[stream.size() / 2] ^= 0x21;
  chunk("IDAT", stream);
  chunk("IEND", {});
  return png;
}

// Smooth gradients with noise: each filter then has work to do, and Paeth takes all three branches.
cv::Mat testImage(int type, uint64_t seed) {
  cv::Mat image(23, 37, type);
  cv::RNG rng(seed);
  const double full = CV_MAT_DEPTH(type) == CV_16U ? 65535 : 255;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double v = full * (0.5 + 0.4 * std::sin(0.3 * x + 0.2 * y)) + rng.gaussian(0.05 * full);
      const double clamped = std::min(full, std::max(0.0, v));
      if (CV_MAT_DEPTH(type) == CV_16U)
        image.at<uint16_t>(y, x) = static_cast<uint16_t>(clamped);
      else
        image.at<uint8_t>(y, x) = static_cast<uint8_t>(clamped);
    }
  return image;
}

TEST(GreyPng, EveryRowFilterBothDepthsAndModesAsOpenCvReadsThem) {
  test::TempDir tmp;
  const std::vector<std::pair<int, const char*>> filters = {
      {PNG_FILTER_NONE, "none"}, {PNG_FILTER_SUB, "sub"},     {PNG_FILTER_UP, "up"},
      {PNG_FILTER_AVG, "average"}, {PNG_FILTER_PAETH, "paeth"}, {PNG_ALL_FILTERS, "adaptive"}};
  for (const int type : {CV_8UC1, CV_16UC1})
    for (const auto& [filter, name] : filters)
      for (const int level : {0, 1, 9}) {
        const cv::Mat image = testImage(type, static_cast<uint64_t>(filter * 10 + level));
        const fs::path file = tmp / (std::string(name) + std::to_string(level) + ".png");
        writeWithLibpng(file, image, filter, level, false);
        const std::vector<uint8_t> bytes = bytesOf(file);
        ASSERT_TRUE(isGreyPng(bytes.data(), bytes.size())) << file;
        for (const auto& [mode, flags] : {std::pair{ImageRead::kGrey, cv::IMREAD_GRAYSCALE},
                                          std::pair{ImageRead::kUnchanged, cv::IMREAD_UNCHANGED}}) {
          const std::string what = std::string(name) + " level " + std::to_string(level) + " type " +
                                   std::to_string(type) + " mode " + std::to_string(flags);
          cv::Mat ours;
          ASSERT_TRUE(decodeGreyPng(bytes.data(), bytes.size(), mode, ours)) << what;
          EXPECT_TRUE(samePixels(ours, cv::imread(file.string(), flags))) << what;
          EXPECT_TRUE(samePixels(readImageFile(file.string(), mode), ours)) << what;
          if (mode == ImageRead::kUnchanged) {
            EXPECT_TRUE(samePixels(ours, image)) << what;
          }
        }
      }
}

TEST(GreyPng, RealEurocFramesAndWhatAdugsWrites) {
  const fs::path dir = test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data";
  ADUGS_REQUIRE_SHARED(dir);
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".png" || ++frames > 12) continue;
    const std::vector<uint8_t> bytes = bytesOf(entry.path());
    cv::Mat ours;
    ASSERT_TRUE(decodeGreyPng(bytes.data(), bytes.size(), ImageRead::kGrey, ours)) << entry.path();
    EXPECT_TRUE(samePixels(ours, cv::imread(entry.path().string(), cv::IMREAD_GRAYSCALE))) << entry.path();
  }
  EXPECT_GE(frames, 12);
  // adugs' own writer (sim, record): filter Sub, zlib's run-length strategy.
  const cv::Mat image = testImage(CV_8UC1, 5);
  const std::vector<uint8_t> written = encodeImage(".png", image, "test");
  cv::Mat ours;
  ASSERT_TRUE(decodeGreyPng(written.data(), written.size(), ImageRead::kGrey, ours));
  EXPECT_TRUE(samePixels(ours, image));
}

// Colour, interlaced and damaged files are not decoded here; the image reader still decodes the
// good ones through libpng and names what is wrong with the others.
TEST(GreyPng, LeavesEverythingElseToLibpng) {
  test::TempDir tmp;
  cv::Mat out;
  const fs::path colour = tmp / "colour.png";
  writeWithLibpng(colour, cv::Mat(9, 11, CV_8UC3, cv::Scalar(10, 20, 30)), PNG_FILTER_SUB, 6, false);
  std::vector<uint8_t> bytes = bytesOf(colour);
  EXPECT_FALSE(isGreyPng(bytes.data(), bytes.size()));
  EXPECT_FALSE(decodeGreyPng(bytes.data(), bytes.size(), ImageRead::kGrey, out));

  const fs::path interlaced = tmp / "interlaced.png";
  const cv::Mat image = testImage(CV_8UC1, 3);
  writeWithLibpng(interlaced, image, PNG_FILTER_PAETH, 6, true);
  bytes = bytesOf(interlaced);
  EXPECT_FALSE(decodeGreyPng(bytes.data(), bytes.size(), ImageRead::kGrey, out));
  EXPECT_TRUE(samePixels(readImageFile(interlaced.string(), ImageRead::kGrey), image));

  const fs::path good = tmp / "good.png";
  writeWithLibpng(good, image, PNG_FILTER_PAETH, 6, false);
  const std::vector<uint8_t> good_bytes = bytesOf(good);
  // A flipped byte in the image data (the chunk's CRC fails), the file cut short, a byte of the
  // zlib stream changed with the CRC recomputed (the stream or its Adler-32 fails), an unknown
  // filter type: each refused here, and by libpng with a reason.
  std::vector<std::pair<std::string, std::vector<uint8_t>>> damaged;
  std::vector<uint8_t> flipped = good_bytes;
  flipped[good_bytes.size() - 30] ^= 0x5a;
  damaged.emplace_back("flipped", flipped);
  damaged.emplace_back("cut", std::vector<uint8_t>(good_bytes.begin(), good_bytes.end() - 20));
  std::vector<uint8_t> rows;
  for (int y = 0; y < image.rows; ++y) {
    rows.push_back(0);
    rows.insert(rows.end(), image.ptr<uint8_t>(y), image.ptr<uint8_t>(y) + image.cols);
  }
  const std::vector<uint8_t> built = pngAround(image.cols, image.rows, rows, false);
  ASSERT_TRUE(decodeGreyPng(built.data(), built.size(), ImageRead::kGrey, out));  // the builder is right
  EXPECT_TRUE(samePixels(out, image));
  out.release();
  damaged.emplace_back("stream", pngAround(image.cols, image.rows, rows, true));
  rows[rows.size() / 2 / static_cast<size_t>(image.cols + 1) * static_cast<size_t>(image.cols + 1)] = 7;
  damaged.emplace_back("filter7", pngAround(image.cols, image.rows, rows, false));
  for (const auto& [name, b] : damaged) {
    EXPECT_FALSE(decodeGreyPng(b.data(), b.size(), ImageRead::kGrey, out)) << name;
    const fs::path file = tmp / (name + ".png");
    test::writeText(file, std::string(b.begin(), b.end()));
    try {
      readImageFile(file.string(), ImageRead::kGrey);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not a readable PNG"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(out.empty()) << "a refused file must leave the output untouched";
}

}  // namespace
}  // namespace adugs::data

// libFuzzer target: arbitrary bytes as a PNG or JPEG file (a bag's compressed image, a dataset's
// frame) through data/formats/image_file, libpng and libjpeg with their longjmp error paths.
// Bytes that start as neither are skipped (they would go to OpenCV in libadugs_media.so, not
// ours to fuzz). Oracles: a decode either gives an image or says why; a grey decode is 8-bit,
// one channel; a decode as stored has one of the types adugs handles and the same size as the
// grey one; an image decoded from PNG, written as PNG and read back is the same to the pixel;
// from JPEG, written as JPEG and read back has the same size and type.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/formats/image_file.h"

namespace {
using namespace adugs::data;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "BUG: %s\n", what.c_str());
  std::abort();
}

bool samePixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

cv::Mat decode(const std::vector<uint8_t>& bytes, ImageRead mode) {
  std::string why;
  cv::Mat image = decodeImage(bytes, mode, &why);
  if (image.empty() && why.empty()) bug("a decode failed without saying why");
  if (!image.empty() && (image.rows < 1 || image.cols < 1)) bug("a decoded image has no pixels");
  return image;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool png = size >= 8 && data[0] == 0x89 && data[1] == 'P' && data[2] == 'N' && data[3] == 'G';
  const bool jpeg = size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
  if (!png && !jpeg) return 0;
  // A header asking for a huge image makes the decoder allocate it before finding the data
  // missing: legitimate (up to 512 MB), but it makes each run slow; small images reach the same code.
  if (png && size >= 24) {
    const uint64_t w = uint64_t{data[16]} << 24 | uint64_t{data[17]} << 16 | uint64_t{data[18]} << 8 | data[19];
    const uint64_t h = uint64_t{data[20]} << 24 | uint64_t{data[21]} << 16 | uint64_t{data[22]} << 8 | data[23];
    if (w * h > (uint64_t{1} << 22)) return 0;
  }
  // The same for a JPEG frame header (SOF0-SOF15 but DHT, JPG, DAC): any that asks for more.
  for (size_t i = 0; jpeg && i + 9 <= size; ++i)
    if (data[i] == 0xFF && data[i + 1] >= 0xC0 && data[i + 1] <= 0xCF && data[i + 1] != 0xC4 &&
        data[i + 1] != 0xC8 && data[i + 1] != 0xCC) {
      const uint64_t h = uint64_t{data[i + 5]} << 8 | data[i + 6], w = uint64_t{data[i + 7]} << 8 | data[i + 8];
      if (w * h > (uint64_t{1} << 22)) return 0;
    }
  const std::vector<uint8_t> bytes(data, data + size);
  const cv::Mat grey = decode(bytes, ImageRead::kGrey);
  const cv::Mat stored = decode(bytes, ImageRead::kUnchanged);
  if (!grey.empty() && grey.type() != CV_8UC1) bug("a grey decode is not 8-bit one channel");
  if (stored.empty()) return 0;
  const int t = stored.type();
  if (t != CV_8UC1 && t != CV_8UC3 && t != CV_8UC4 && t != CV_16UC1 && t != CV_16UC3 && t != CV_16UC4)
    bug("a decode as stored has type " + std::to_string(t));
  if (!grey.empty() && grey.size() != stored.size()) bug("the grey and stored decodes differ in size");
  if (stored.total() > 4'000'000) return 0;  // the round trips below: small images are enough
  const std::vector<uint8_t> again = encodeImage(png ? ".png" : ".jpg", stored, "fuzz");
  const cv::Mat back = decode(again, ImageRead::kUnchanged);
  if (png && !samePixels(back, stored)) bug("a PNG written and read back differs");
  if (jpeg && (back.size() != stored.size() || back.type() != stored.type())) bug("a JPEG written and read back differs in size or type");
  return 0;
}

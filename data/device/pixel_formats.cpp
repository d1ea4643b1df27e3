#include "data/device/pixel_formats.h"

#include <opencv2/imgproc.hpp>

namespace adugs::data {
namespace {

constexpr uint32_t makeFourcc(char a, char b, char c, char d) {
  return static_cast<uint32_t>(static_cast<uint8_t>(a)) | (static_cast<uint32_t>(static_cast<uint8_t>(b)) << 8) |
         (static_cast<uint32_t>(static_cast<uint8_t>(c)) << 16) | (static_cast<uint32_t>(static_cast<uint8_t>(d)) << 24);
}

// The row stride to use and whether `bytes` hold the whole image.
bool layout(PixelFormat format, size_t bytes, int width, int height, int bytes_per_line, size_t* stride) {
  if (width <= 0 || height <= 0 || bytes_per_line < 0) return false;
  const size_t packed = static_cast<size_t>(width) * bytesPerPixel(format);
  *stride = bytes_per_line == 0 ? packed : static_cast<size_t>(bytes_per_line);
  if (*stride < packed) return false;
  // The last row needs only its pixels, not its padding.
  return bytes >= *stride * static_cast<size_t>(height - 1) + packed;
}

}  // namespace

uint32_t fourcc(PixelFormat format) {
  switch (format) {
    case PixelFormat::kGrey: return makeFourcc('G', 'R', 'E', 'Y');
    case PixelFormat::kY8i: return makeFourcc('Y', '8', 'I', ' ');
    case PixelFormat::kYuyv: return makeFourcc('Y', 'U', 'Y', 'V');
  }
  return 0;
}

bool pixelFormatFromFourcc(uint32_t code, PixelFormat* format) {
  for (PixelFormat f : {PixelFormat::kGrey, PixelFormat::kY8i, PixelFormat::kYuyv}) {
    if (fourcc(f) == code) {
      *format = f;
      return true;
    }
  }
  return false;
}

std::string toString(PixelFormat format) { return fourccText(fourcc(format)); }

std::string fourccText(uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((code >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

int bytesPerPixel(PixelFormat format) { return format == PixelFormat::kGrey ? 1 : 2; }

bool decodeGrey(PixelFormat format, const uint8_t* data, size_t bytes, int width, int height,
                int bytes_per_line, cv::Mat* grey) {
  size_t stride = 0;
  if (!data || !layout(format, bytes, width, height, bytes_per_line, &stride)) return false;
  cv::Mat out(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = data + stride * static_cast<size_t>(y);
    uint8_t* dst = out.ptr<uint8_t>(y);
    if (format == PixelFormat::kGrey) {
      std::copy(row, row + width, dst);
    } else {
      // Y8I: left = byte 0 of each pair; YUYV: luma = byte 0 of each pair.
      for (int x = 0; x < width; ++x) dst[x] = row[2 * x];
    }
  }
  *grey = out;
  return true;
}

bool decodeYuyvToBgr(const uint8_t* data, size_t bytes, int width, int height, int bytes_per_line, cv::Mat* bgr) {
  size_t stride = 0;
  if (!data || width % 2 != 0 || !layout(PixelFormat::kYuyv, bytes, width, height, bytes_per_line, &stride)) return false;
  // A view of the driver's bytes (not written), converted into a new image.
  const cv::Mat yuyv(height, width, CV_8UC2, const_cast<uint8_t*>(data), stride);
  cv::cvtColor(yuyv, *bgr, cv::COLOR_YUV2BGR_YUYV);
  return true;
}

bool splitY8i(const uint8_t* data, size_t bytes, int width, int height, int bytes_per_line,
              cv::Mat* left, cv::Mat* right) {
  size_t stride = 0;
  if (!data || !layout(PixelFormat::kY8i, bytes, width, height, bytes_per_line, &stride)) return false;
  cv::Mat l(height, width, CV_8UC1), r(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = data + stride * static_cast<size_t>(y);
    uint8_t* dl = l.ptr<uint8_t>(y);
    uint8_t* dr = r.ptr<uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      dl[x] = row[2 * x];
      dr[x] = row[2 * x + 1];
    }
  }
  *left = l;
  *right = r;
  return true;
}

}  // namespace adugs::data

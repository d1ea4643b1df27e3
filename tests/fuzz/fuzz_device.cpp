// libFuzzer target: arbitrary bytes as what a camera or the kernel hands the live source: a UVC
// metadata buffer, an IIO scan-element type and record, an image buffer of some size and stride,
// and a run of 32-bit counter values with host arrival times for the device clock. The decoders
// must refuse what does not fit (false, or InputError for the scan type) and never read past the
// buffer; anything else (a crash, another exception, a sanitizer report) is a bug. Oracles on what
// they accept: a scan type is consistent (1 <= real bits <= storage bits, shift + real bits within
// the storage), every decoded IIO value lies in its type's range, a decoded image has the size
// asked for, and an unwrapped counter keeps the raw value's low 32 bits within half a wrap of
// the newest one.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <algorithm>
#include <climits>
#include <vector>

#include <opencv2/core.hpp>

#include "data/device/device_clock.h"
#include "data/device/iio_scan.h"
#include "data/device/pixel_formats.h"
#include "data/device/uvc_metadata.h"
#include "data/input_error.h"

namespace {
using namespace adugs::data;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "BUG: %s\n", what.c_str());
  std::abort();
}

uint32_t le32(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }

void metadata(const uint8_t* data, size_t size) {
  UvcFrameMetadata m;
  parseUvcMetadata(data, size, &m);
}

// The first line is a scan type; the rest a record of three such channels and a timestamp.
void iio(const uint8_t* data, size_t size) {
  const uint8_t* end = static_cast<const uint8_t*>(std::memchr(data, '\n', size));
  if (!end) return;
  const std::string text(reinterpret_cast<const char*>(data), static_cast<size_t>(end - data));
  try {
    const IioScanType t = parseIioScanType(text, "fuzz_type");
    if (t.real_bits < 1 || t.real_bits > t.storage_bits || t.shift < 0 || t.shift + t.real_bits > t.storage_bits ||
        t.repeat < 1)
      bug("inconsistent scan type accepted: " + text);
    std::vector<IioChannel> channels = {{"x", 0, t, 0}, {"y", 1, t, 0}, {"z", 2, t, 0},
                                        {"timestamp", 3, parseIioScanType("le:s64/64>>0", "ts"), 0}};
    const size_t record = layoutIioRecord(&channels, "fuzz");
    const uint8_t* bytes = end + 1;
    const size_t left = size - static_cast<size_t>(bytes - data);
    if (left < record) return;
    for (const IioChannel& c : channels)
      for (int e = 0; e < c.type.repeat; ++e) {
        const int64_t v = decodeIioValue(bytes, c, e);
        const int r = c.type.real_bits;
        if (r >= 64) continue;
        const int64_t lo = c.type.is_signed ? -(int64_t{1} << (r - 1)) : 0;
        const uint64_t hi = c.type.is_signed ? (uint64_t{1} << (r - 1)) - 1 : (uint64_t{1} << r) - 1;
        if (v < lo || (v >= 0 && static_cast<uint64_t>(v) > hi))
          bug("IIO value " + std::to_string(v) + " out of the range of " + text);
      }
  } catch (const InputError&) {
  }
}

// width, height (1..64), stride (0..255) from the first bytes, the image after them.
void pixels(const uint8_t* data, size_t size) {
  if (size < 3) return;
  const int width = 1 + data[0] % 64, height = 1 + data[1] % 64, stride = data[2];
  data += 3;
  size -= 3;
  cv::Mat a, b;
  auto expect = [&](const cv::Mat& m, int type, const char* what) {
    if (m.cols != width || m.rows != height || m.type() != type)
      bug(std::string(what) + ": decoded " + std::to_string(m.cols) + "x" + std::to_string(m.rows) + " for " +
          std::to_string(width) + "x" + std::to_string(height));
  };
  for (PixelFormat f : {PixelFormat::kGrey, PixelFormat::kY8i, PixelFormat::kYuyv})
    if (decodeGrey(f, data, size, width, height, stride, &a)) expect(a, CV_8UC1, "decodeGrey");
  if (splitY8i(data, size, width, height, stride, &a, &b)) {
    expect(a, CV_8UC1, "splitY8i left");
    expect(b, CV_8UC1, "splitY8i right");
  }
  if (decodeYuyvToBgr(data, size, width, height, stride, &a)) expect(a, CV_8UC3, "decodeYuyvToBgr");
}

// Pairs of (32-bit counter, host delay in us): a device 1 us per us, arbitrary jitter and wraps.
void clock(const uint8_t* data, size_t size) {
  CounterUnwrapper unwrapper(32);
  DeviceClockMapper mapper;
  int64_t host = 1'000'000'000'000'000;
  int64_t newest = INT64_MIN;
  for (size_t i = 0; i + 8 <= size; i += 8) {
    const uint32_t raw = le32(data + i);
    const int64_t device = unwrapper.unwrap(raw);
    if (static_cast<uint32_t>(static_cast<uint64_t>(device)) != raw)
      bug("unwrapped counter " + std::to_string(device) + " does not end in the raw " + std::to_string(raw));
    if (newest != INT64_MIN && (device - newest > (int64_t{1} << 31) || newest - device > (int64_t{1} << 31)))
      bug("unwrapped counter jumped more than half a wrap: " + std::to_string(newest) + " -> " + std::to_string(device));
    newest = std::max(newest, device);
    host += 1000 * static_cast<int64_t>(le32(data + i + 4) % 100'000);  // up to 0.1 s later
    mapper.addPair(device, host);
    mapper.toHostNs(device);
    mapper.driftPpm();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t* rest = data + 1;
  const size_t n = size - 1;
  switch (data[0] % 4) {
    case 0: metadata(rest, n); break;
    case 1: iio(rest, n); break;
    case 2: pixels(rest, n); break;
    default: clock(rest, n); break;
  }
  return 0;
}

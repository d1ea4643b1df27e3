// libFuzzer target: arbitrary bytes as what a camera or the kernel hands the live source: a UVC
// metadata buffer, an IIO scan-element type and record, an image buffer of some size and stride,
// and a run of 32-bit counter values with host arrival times for the device clock. The decoders
// must refuse what does not fit (false, or InputError for the scan type) and never read past the
// buffer; anything else (a crash, another exception, a sanitizer report) is a bug.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/device/device_clock.h"
#include "data/device/iio_scan.h"
#include "data/device/pixel_formats.h"
#include "data/device/uvc_metadata.h"
#include "data/input_error.h"

namespace {
using namespace adugs::data;

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
    std::vector<IioChannel> channels = {{"x", 0, t, 0}, {"y", 1, t, 0}, {"z", 2, t, 0},
                                        {"timestamp", 3, parseIioScanType("le:s64/64>>0", "ts"), 0}};
    const size_t record = layoutIioRecord(&channels, "fuzz");
    const uint8_t* bytes = end + 1;
    const size_t left = size - static_cast<size_t>(bytes - data);
    if (left < record) return;
    for (const IioChannel& c : channels)
      for (int e = 0; e < c.type.repeat; ++e) decodeIioValue(bytes, c, e);
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
  for (PixelFormat f : {PixelFormat::kGrey, PixelFormat::kY8i, PixelFormat::kYuyv}) decodeGrey(f, data, size, width, height, stride, &a);
  splitY8i(data, size, width, height, stride, &a, &b);
  decodeYuyvToBgr(data, size, width, height, stride, &a);
}

// Pairs of (32-bit counter, host delay in us): a device 1 us per us, arbitrary jitter and wraps.
void clock(const uint8_t* data, size_t size) {
  CounterUnwrapper unwrapper(32);
  DeviceClockMapper mapper;
  int64_t host = 1'000'000'000'000'000;
  for (size_t i = 0; i + 8 <= size; i += 8) {
    const int64_t device = unwrapper.unwrap(le32(data + i));
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

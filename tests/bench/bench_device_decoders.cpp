// Cost of the live D435i path per measurement (data/device): a 848x480 frame decoded from each
// pixel format, its metadata parsed, an IIO record decoded, a device stamp mapped to the host.
// Run: build/tests/bench/bench_device_decoders (figures in doc/results.md).
#include <benchmark/benchmark.h>

#include <vector>

#include <opencv2/core.hpp>

#include "data/device/device_clock.h"
#include "data/device/iio_scan.h"
#include "data/device/pixel_formats.h"
#include "data/device/uvc_metadata.h"
#include "tests/device_bytes.h"

namespace {
using namespace adugs::data;

constexpr int kW = 848, kH = 480;

void BM_DecodeGrey(benchmark::State& state) {
  const PixelFormat format = static_cast<PixelFormat>(state.range(0));
  std::vector<uint8_t> bytes(static_cast<size_t>(kW) * kH * bytesPerPixel(format), 100);
  cv::Mat grey;
  for (auto _ : state) {
    decodeGrey(format, bytes.data(), bytes.size(), kW, kH, 0, &grey);
    benchmark::DoNotOptimize(grey.data);
  }
  state.SetLabel(toString(format));
}
BENCHMARK(BM_DecodeGrey)->Arg(static_cast<int>(PixelFormat::kGrey))->Arg(static_cast<int>(PixelFormat::kY8i))
    ->Arg(static_cast<int>(PixelFormat::kYuyv))->Unit(benchmark::kMicrosecond);

void BM_YuyvToBgr(benchmark::State& state) {
  std::vector<uint8_t> bytes(static_cast<size_t>(kW) * kH * 2, 128);
  cv::Mat bgr;
  for (auto _ : state) {
    decodeYuyvToBgr(bytes.data(), bytes.size(), kW, kH, 0, &bgr);
    benchmark::DoNotOptimize(bgr.data);
  }
}
BENCHMARK(BM_YuyvToBgr)->Unit(benchmark::kMicrosecond);

void BM_ParseMetadata(benchmark::State& state) {
  adugs::test::D4xxMetadataFields f;
  f.sensor_timestamp_us = 123456;
  const std::vector<uint8_t> block = adugs::test::d4xxMetadataBlock(f);
  UvcFrameMetadata m;
  for (auto _ : state) {
    parseUvcMetadata(block.data(), block.size(), &m);
    benchmark::DoNotOptimize(m.sensor_timestamp_us);
  }
}
BENCHMARK(BM_ParseMetadata);

void BM_DecodeIioRecord(benchmark::State& state) {
  std::vector<IioChannel> c = {{"x", 0, parseIioScanType("le:s16/32>>0", "x"), 0},
                               {"y", 1, parseIioScanType("le:s16/32>>0", "y"), 0},
                               {"z", 2, parseIioScanType("le:s16/32>>0", "z"), 0},
                               {"timestamp", 3, parseIioScanType("le:s64/64>>0", "t"), 0}};
  layoutIioRecord(&c, "bench");
  const std::vector<uint8_t> record = adugs::test::hidImuRecord(-2, 300, -450, 4'000'000'000'000, 2);
  for (auto _ : state) {
    int64_t sum = 0;
    for (const IioChannel& ch : c) sum += decodeIioValue(record.data(), ch);
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_DecodeIioRecord);

// One pair added and one stamp mapped, as for every IMU read (refit over a 30 s window).
void BM_ClockPairAndMap(benchmark::State& state) {
  DeviceClockMapper mapper;
  int64_t d = 0;
  for (; d < 30'000'000; d += 1538) mapper.addPair(d, 1'000'000'000 + d * 1000 + (d % 7) * 10'000);
  for (auto _ : state) {
    d += 1538;
    mapper.addPair(d, 1'000'000'000 + d * 1000 + (d % 7) * 10'000);
    benchmark::DoNotOptimize(mapper.toHostNs(d));
  }
}
BENCHMARK(BM_ClockPairAndMap);

}  // namespace

BENCHMARK_MAIN();

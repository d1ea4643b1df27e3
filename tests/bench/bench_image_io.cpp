// Reading the real EuRoC PNGs (752x480, 8-bit grey; ../shared/data/euroc_v101_micro) into the
// cv::Mat the front-end tracks on: the product's data::readImageFile (grey frames inflated with
// libdeflate, other PNGs through libpng: what the readers use since OpenCV's imgcodecs became a
// module), OpenCV's cv::imread (what they used before) and ViSP's display-less vpImageIo (its
// default backend, then converted to cv::Mat); and writing them back as PNG the three ways.
// items_per_second = images per second on one core. The *Written variants read the same frames as
// adugs' writer stores them (`adugs sim`, `adugs record`: filter Sub, zlib's run-length strategy),
// which unlike EuRoC's stored (uncompressed) ones are deflated.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>
#include <visp3/core/vpImageConvert.h>
#include <visp3/io/vpImageIo.h>

#include "data/formats/image_file.h"
#include "tests/test_support.h"

namespace {

std::vector<std::string> eurocImages() {
  std::vector<std::string> paths;
  const std::filesystem::path dir = adugs::test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data";
  if (!std::filesystem::is_directory(dir)) return paths;
  for (const auto& e : std::filesystem::directory_iterator(dir)) paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

cv::Mat readWithAdugs(const std::string& path) {
  return adugs::data::readImageFile(path, adugs::data::ImageRead::kGrey);
}
cv::Mat readWithOpenCv(const std::string& path) { return cv::imread(path, cv::IMREAD_GRAYSCALE); }

// Reads the files in turn, one per iteration.
void readAll(benchmark::State& state, const std::vector<std::string>& paths, cv::Mat (*read)(const std::string&)) {
  if (paths.empty()) return state.SkipWithError("../shared/data/euroc_v101_micro is absent");
  size_t i = 0;
  for (auto _ : state) {
    cv::Mat image = read(paths[i++ % paths.size()]);
    benchmark::DoNotOptimize(image.data);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_ReadImageFile(benchmark::State& state) { readAll(state, eurocImages(), readWithAdugs); }

// The frames re-encoded by data::writeImageFile into a folder that lives as long as the process.
const std::vector<std::string>& writtenImages() {
  static adugs::test::TempDir dir("adugs_bench_image_io_written");
  static std::vector<std::string> paths;
  if (paths.empty())
    for (const std::string& p : eurocImages()) {
      paths.push_back((dir / std::filesystem::path(p).filename()).string());
      adugs::data::writeImageFile(paths.back(), cv::imread(p, cv::IMREAD_GRAYSCALE));
    }
  return paths;
}

void BM_ReadImageFileWritten(benchmark::State& state) { readAll(state, writtenImages(), readWithAdugs); }

void BM_ReadOpenCvWritten(benchmark::State& state) { readAll(state, writtenImages(), readWithOpenCv); }

void BM_ReadOpenCv(benchmark::State& state) { readAll(state, eurocImages(), readWithOpenCv); }

void BM_ReadVispImageIo(benchmark::State& state) {
  const std::vector<std::string> paths = eurocImages();
  if (paths.empty()) return state.SkipWithError("../shared/data/euroc_v101_micro is absent");
  size_t i = 0;
  vpImage<unsigned char> image;
  for (auto _ : state) {
    vpImageIo::read(image, paths[i++ % paths.size()]);
    cv::Mat mat;
    vpImageConvert::convert(image, mat);
    benchmark::DoNotOptimize(mat.data);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_WriteImageFile(benchmark::State& state) {
  const std::vector<std::string> paths = eurocImages();
  if (paths.empty()) return state.SkipWithError("../shared/data/euroc_v101_micro is absent");
  const cv::Mat image = cv::imread(paths.front(), cv::IMREAD_GRAYSCALE);
  adugs::test::TempDir dir("adugs_bench_image_io");
  const std::string out = (dir / "frame.png").string();
  for (auto _ : state) adugs::data::writeImageFile(out, image);
  state.SetItemsProcessed(state.iterations());
}

void BM_WriteOpenCv(benchmark::State& state) {
  const std::vector<std::string> paths = eurocImages();
  if (paths.empty()) return state.SkipWithError("../shared/data/euroc_v101_micro is absent");
  const cv::Mat image = cv::imread(paths.front(), cv::IMREAD_GRAYSCALE);
  adugs::test::TempDir dir("adugs_bench_image_io");
  const std::string out = (dir / "frame.png").string();
  for (auto _ : state) benchmark::DoNotOptimize(cv::imwrite(out, image));
  state.SetItemsProcessed(state.iterations());
}

void BM_WriteVispImageIo(benchmark::State& state) {
  const std::vector<std::string> paths = eurocImages();
  if (paths.empty()) return state.SkipWithError("../shared/data/euroc_v101_micro is absent");
  vpImage<unsigned char> image;
  vpImageIo::read(image, paths.front());
  adugs::test::TempDir dir("adugs_bench_image_io");
  const std::string out = (dir / "frame.png").string();
  for (auto _ : state) vpImageIo::write(image, out);
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK(BM_ReadImageFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadOpenCv)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadVispImageIo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadImageFileWritten)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadOpenCvWritten)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteImageFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteOpenCv)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteVispImageIo)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

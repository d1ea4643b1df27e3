// Bag playback speed: a bag of 752x480 bgr8 images at 20 Hz with a 200 Hz IMU (VIODE layout),
// written by the C++ rosbag library, plain / bz2 / lz4, read through RosbagSource (decoding,
// reordering, conversion to grey). items_per_second = frames delivered per second on one core.
#include <benchmark/benchmark.h>

#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "data/sources/rosbag_source.h"
#include "tests/test_support.h"

namespace {

using namespace adugs;
constexpr int kFrames = 100;

std::string writeBag(rosbag::compression::CompressionType compression, const std::string& name) {
  static adugs::test::TempDir dir("adugs_bench_bag");
  const std::string path = (dir / name).string();
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  cv::Mat picture(480, 752, CV_8UC3);
  cv::randu(picture, 0, 255);
  cv::GaussianBlur(picture, picture, {0, 0}, 3.0);  // some texture, compressible like a photo
  const ros::Time t0(1700000000, 0);
  // Written in record-time order, as a recorder does: each image 20 ms after its stamp, each IMU
  // sample 1 ms after.
  sensor_msgs::Image pending;
  ros::Time pending_record;
  bool has_pending = false;
  for (int i = 0; i < kFrames * 10; ++i) {  // IMU at 200 Hz
    sensor_msgs::Imu imu;
    imu.header.stamp = t0 + ros::Duration(i * 0.005);
    imu.linear_acceleration.z = 9.81;
    const ros::Time record = imu.header.stamp + ros::Duration(0.001);
    if (has_pending && pending_record <= record) {
      bag.write("/cam0/image_raw", pending_record, pending);
      has_pending = false;
    }
    bag.write("/imu0", record, imu);
    if (i % 10 != 0) continue;
    sensor_msgs::Image image;
    image.header.stamp = imu.header.stamp;
    image.width = 752;
    image.height = 480;
    image.encoding = "bgr8";
    image.step = 752 * 3;
    image.data.assign(picture.data, picture.data + picture.total() * 3);
    pending = image;
    pending_record = image.header.stamp + ros::Duration(0.02);
    has_pending = true;
  }
  if (has_pending) bag.write("/cam0/image_raw", pending_record, pending);
  bag.close();
  return path;
}

void playBag(benchmark::State& state, rosbag::compression::CompressionType compression, const char* name) {
  static std::map<std::string, std::string> paths;
  if (!paths.count(name)) paths[name] = writeBag(compression, name);
  data::RosbagSourceOptions options;
  options.topics.image = "/cam0/image_raw";
  options.topics.imu = "/imu0";
  size_t frames = 0;
  for (auto _ : state) {
    data::RosbagSource source(paths[name], options);
    data::Measurement m;
    while (source.next(m)) {
      if (m.isFrame()) {
        benchmark::DoNotOptimize(m.frame.image.data);
        ++frames;
      }
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(frames));
}

void BM_BagPlaybackBgr8Plain(benchmark::State& s) { playBag(s, rosbag::compression::Uncompressed, "plain.bag"); }
void BM_BagPlaybackBgr8Lz4(benchmark::State& s) { playBag(s, rosbag::compression::LZ4, "lz4.bag"); }
void BM_BagPlaybackBgr8Bz2(benchmark::State& s) { playBag(s, rosbag::compression::BZ2, "bz2.bag"); }

BENCHMARK(BM_BagPlaybackBgr8Plain)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_BagPlaybackBgr8Lz4)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_BagPlaybackBgr8Bz2)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();

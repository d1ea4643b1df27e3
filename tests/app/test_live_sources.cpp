// The live sources of `adugs live` / `adugs record` on their own (app/live_sources.h chooses them
// from data/sources/): the D435i-like replay's delivery (time order, pace, packets, lost frames, stop), the video played as a camera.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "app/live_sources.h"
#include "data/input_error.h"
#include "data/sources/replay_source.h"
#include "data/sources/video_file_source.h"
#include "tests/test_support.h"

namespace adugs::app {
namespace {

using Clock = std::chrono::steady_clock;

// A recorded sequence in memory: IMU at 200 Hz, frames at 30 Hz, `seconds` long.
class VectorSource : public data::SequenceSource {
 public:
  explicit VectorSource(double seconds) {
    const int64_t end = data::secToNs(seconds);
    int64_t t_imu = 0, t_cam = 0;
    while (t_imu <= end || t_cam <= end) {
      data::Measurement m;
      if (t_imu <= t_cam) {
        m.type = data::Measurement::Type::kImu;
        m.imu.t_ns = t_imu;
        t_imu += 5'000'000;
      } else {
        m.type = data::Measurement::Type::kFrame;
        m.frame.t_ns = t_cam;
        t_cam += 33'333'333;
      }
      if (m.timeNs() <= end) all_.push_back(m);
    }
  }
  bool next(data::Measurement& m) override {
    if (i_ >= all_.size()) return false;
    m = all_[i_++];
    return true;
  }
  data::SourceCounts counts() const override { return {}; }
  std::string description() const override { return "vector"; }
  const std::vector<data::Measurement>& all() const { return all_; }

 private:
  std::vector<data::Measurement> all_;
  size_t i_ = 0;
};

struct Delivered {
  data::Measurement m;
  double wall_s;  // since the first call of next() (the source's clock starts after it)
};

std::vector<Delivered> drain(data::SequenceSource& s) {
  std::vector<Delivered> out;
  data::Measurement m;
  const Clock::time_point start = Clock::now();
  while (s.next(m)) out.push_back({m, std::chrono::duration<double>(Clock::now() - start).count()});
  return out;
}

TEST(ReplaySource, DeliversInTimeOrderAtSensorPaceWithLateFramesAndImuPackets) {
  const double speed = 4;  // 3 s of sensor time in 0.75 s
  auto inner = std::make_unique<VectorSource>(3.0);
  const std::vector<data::Measurement> recorded = inner->all();
  data::ReplayTiming timing;
  timing.speed = speed;
  timing.frame_loss = 0;
  data::ReplaySource replay(std::move(inner), timing);
  EXPECT_TRUE(replay.isLive());
  const std::vector<Delivered> got = drain(replay);
  ASSERT_EQ(got.size(), recorded.size());  // nothing lost at frame_loss 0
  double max_early_s = 0;
  int frames = 0, imu_after_imu_without_wait = 0, imu = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].m.timeNs(), recorded[i].timeNs());  // same measurements, same order
    // Never before its stamp (sensor pace), frames at least latency - jitter = 10 ms late.
    const double sensor_s = data::nsToSec(got[i].m.timeNs()) / speed;
    const double late_min = got[i].m.isFrame() ? 0.010 / speed : 0.0;
    max_early_s = std::max(max_early_s, sensor_s + late_min - got[i].wall_s);
    frames += got[i].m.isFrame();
    if (got[i].m.isImu() && i > 0 && got[i - 1].m.isImu()) {
      ++imu;
      imu_after_imu_without_wait += got[i].wall_s - got[i - 1].wall_s < 0.5e-3;
    }
  }
  EXPECT_LE(max_early_s, 0.0);  // never early
  EXPECT_EQ(frames, 91);
  // The IMU comes in packets of two 5 ms samples (10 ms bursts): about half the IMU samples that
  // follow another one arrive with it, at once.
  EXPECT_GT(imu_after_imu_without_wait, imu / 4);
  // At sensor pace: the 3 s took at least 0.75 s (how much longer depends on the machine's load;
  // the bound only catches a hang).
  EXPECT_GE(got.back().wall_s, 3.0 / speed);
  EXPECT_LT(got.back().wall_s, 20.0);
}

TEST(ReplaySource, LosesTheGivenFractionOfFramesAndCountsThem) {
  auto inner = std::make_unique<VectorSource>(20.0);
  data::ReplayTiming timing;
  timing.speed = 100;
  timing.frame_loss = 0.1;
  timing.seed = 7;
  data::ReplaySource replay(std::move(inner), timing);
  const std::vector<Delivered> got = drain(replay);
  int frames = 0, imu = 0;
  for (const Delivered& d : got) (d.m.isFrame() ? frames : imu)++;
  EXPECT_EQ(imu, 4001);  // every IMU sample
  EXPECT_EQ(static_cast<size_t>(frames) + replay.counts().frames_lost, 601u);
  EXPECT_NEAR(replay.counts().frames_lost, 60, 20);
}

TEST(ReplaySource, StopEndsAWaitingNextFromAnotherThread) {
  data::ReplayTiming timing;
  timing.speed = 1e-4;  // 10,000 s per sensor second: the next sample is 50 s away
  data::ReplaySource replay(std::make_unique<VectorSource>(10.0), timing);
  data::Measurement m;
  ASSERT_TRUE(replay.next(m));  // the first one comes at once
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    replay.stop();
  });
  // Only stop() can make this next() return false (waiting would return the next sample).
  EXPECT_FALSE(replay.next(m));
  stopper.join();
  EXPECT_FALSE(replay.next(m));
}

// A small colour video written here, played as a camera: colour and grey images, stamps from the
// stream, delivered at its frame rate.
TEST(VideoFileSource, PlaysAVideoAtItsFrameRateWithColourAndGrey) {
  test::TempDir dir;
  const std::string path = (dir / "clip.avi").string();
  {
    cv::VideoWriter w(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0, {160, 120});
    ASSERT_TRUE(w.isOpened());
    for (int i = 0; i < 10; ++i) {
      cv::Mat f(120, 160, CV_8UC3, cv::Scalar(0, 0, 0));
      cv::rectangle(f, {10 + 10 * i, 40}, {40 + 10 * i, 80}, cv::Scalar(0, 0, 255), cv::FILLED);
      w.write(f);
    }
  }
  data::VideoFileSource video(path, 2.0);  // 25 Hz at 2x: 20 ms apart
  EXPECT_EQ(video.width(), 160);
  EXPECT_EQ(video.height(), 120);
  EXPECT_NEAR(video.frameRateHz(), 25.0, 1e-6);
  const std::vector<Delivered> got = drain(video);
  ASSERT_EQ(got.size(), 10u);
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].m.frame.t_ns, static_cast<int64_t>(i) * 40'000'000);
    EXPECT_GE(got[i].wall_s, i * 0.020);  // never before its time (later only by the machine's load)
    ASSERT_EQ(got[i].m.frame.colour.type(), CV_8UC3);
    ASSERT_EQ(got[i].m.frame.image.type(), CV_8UC1);
  }
  EXPECT_LT(got.back().wall_s, 20.0);  // only catches a hang
  const cv::Vec3b red = got[3].m.frame.colour.at<cv::Vec3b>(60, 55);  // inside frame 3's square
  EXPECT_GT(red[2], 200);
  EXPECT_LT(red[1], 60);
}

TEST(LiveSources, VisionOnlyCameraIsGuessedOrReadFromKalibrAndMustMatchTheImageSize) {
  std::string from;
  const data::CameraCalibration guess = visionOnlyCamera(640, 480, 30, {}, &from);
  EXPECT_EQ(guess.fx, 640);
  EXPECT_EQ(guess.cx, 319.5);
  EXPECT_NE(from.find("guessed"), std::string::npos);
  test::TempDir dir;
  test::writeText(dir / "camchain.yaml",
                  "cam0:\n  camera_model: pinhole\n  intrinsics: [458.6, 457.3, 367.2, 248.4]\n"
                  "  distortion_model: radtan\n  distortion_coeffs: [-0.28, 0.07, 0.0002, 0.00002]\n"
                  "  resolution: [752, 480]\n");
  const data::CameraCalibration kalibr = visionOnlyCamera(752, 480, 20, {(dir / "camchain.yaml").string()}, &from);
  EXPECT_DOUBLE_EQ(kalibr.fx, 458.6);
  EXPECT_EQ(kalibr.rate_hz, 20);
  try {
    visionOnlyCamera(640, 480, 30, {(dir / "camchain.yaml").string()}, &from);
    FAIL() << "a camchain of another resolution was accepted";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("752x480"), std::string::npos) << e.what();
  }
  // The calibration of a camera with an IMU is refused: these sources have none.
  test::writeText(dir / "imu.yaml",
                  "accelerometer_noise_density: 0.01\naccelerometer_random_walk: 0.0002\n"
                  "gyroscope_noise_density: 0.005\ngyroscope_random_walk: 4.0e-06\n");
  try {
    visionOnlyCamera(752, 480, 20, {(dir / "camchain.yaml").string(), (dir / "imu.yaml").string()}, &from);
    FAIL() << "an IMU file was accepted for a vision-only source";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no IMU"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adugs::app

// EurocReader: the real micro sequence, and small synthetic sequences with every kind of bad input.
#include <fstream>
#include <optional>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"
#include "data/sources/euroc_reader.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;
using adugs::test::TempDir;
using adugs::test::writeText;

constexpr int kWidth = 32, kHeight = 24;

// A small valid sequence: frames at 1000, 1100, ... ns; IMU every 50 ns from 1000 (so the first
// frame shares its timestamp with an IMU sample). data.csv row i is on line i + 2.
struct Sequence {
  TempDir dir;
  fs::path mav() const { return dir.path() / "mav0"; }
  fs::path camCsv() const { return mav() / "cam0" / "data.csv"; }
  fs::path imuCsv() const { return mav() / "imu0" / "data.csv"; }
  fs::path image(int i) const { return mav() / "cam0" / "data" / (std::to_string(frameTime(i)) + ".png"); }
  static int64_t frameTime(int i) { return 1000 + 100 * i; }

  explicit Sequence(int frames = 4, int imu = 8) {
    CameraCalibration cam;
    cam.width = kWidth;
    cam.height = kHeight;
    cam.fx = cam.fy = 30;
    cam.cx = 16;
    cam.cy = 12;
    cam.distortion = {0, 0, 0, 0};
    cam.rate_hz = 20;
    fs::create_directories(mav() / "cam0" / "data");
    fs::create_directories(mav() / "imu0");
    writeEurocCameraYaml((mav() / "cam0" / "sensor.yaml").string(), cam);
    ImuNoise noise;
    noise.rate_hz = noise.gyro_noise_density = noise.gyro_random_walk = 1;
    noise.accel_noise_density = noise.accel_random_walk = 1;
    writeEurocImuYaml((mav() / "imu0" / "sensor.yaml").string(), noise);
    std::string csv = "#timestamp [ns],filename\n";
    for (int i = 0; i < frames; ++i) {
      csv += std::to_string(frameTime(i)) + "," + std::to_string(frameTime(i)) + ".png\n";
      cv::imwrite(image(i).string(), cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(10 * i)));
    }
    writeText(camCsv(), csv);
    std::string imu_csv = "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n";
    for (int i = 0; i < imu; ++i) imu_csv += imuRow(1000 + 50 * i);
    writeText(imuCsv(), imu_csv);
  }

  static std::string imuRow(int64_t t, const std::string& a_y = "0.2") {
    return std::to_string(t) + ",0.01,0.02,0.03,9.81," + a_y + ",-0.1\n";
  }

  // Replaces one line (1-based) of a file.
  static void setLine(const fs::path& file, int line, const std::string& text) {
    std::ifstream in(file);
    std::string all, l;
    for (int n = 1; std::getline(in, l); ++n) all += (n == line ? text : l) + "\n";
    writeText(file, all);
  }
};

std::vector<Measurement> readAll(const std::string& root, EurocReaderOptions options = {}) {
  EurocReader reader(root, options);
  std::vector<Measurement> out;
  Measurement m;
  while (reader.next(m)) out.push_back(m);
  return out;
}

std::optional<InputError> errorReading(const std::string& root, EurocReaderOptions options = {}) {
  try {
    readAll(root, options);
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

// The error names file, line and field, and the message shows all three.
void expectLocated(const std::optional<InputError>& err, const fs::path& file, long line, const std::string& field,
                   const std::string& words) {
  ASSERT_TRUE(err) << "no InputError";
  std::string msg = err->what();
  EXPECT_EQ(err->file(), file.string()) << msg;
  EXPECT_EQ(err->line(), line) << msg;
  EXPECT_EQ(err->field(), field) << msg;
  std::string where = file.string() + (line > 0 ? ":" + std::to_string(line) : "") + ": ";
  EXPECT_EQ(msg.rfind(where, 0), 0u) << msg;
  if (!field.empty()) {
    EXPECT_NE(msg.find("field '" + field + "'"), std::string::npos) << msg;
  }
  EXPECT_NE(msg.find(words), std::string::npos) << msg;
}

size_t countFrames(const std::vector<Measurement>& ms) {
  size_t n = 0;
  for (const Measurement& m : ms) n += m.isFrame();
  return n;
}

TEST(EurocReader, StreamsRealMicroSequence) {
  fs::path root = adugs::test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(root);
  EurocReader reader(root.string());
  EXPECT_DOUBLE_EQ(reader.camera().fx, 458.654);
  EXPECT_DOUBLE_EQ(reader.camera().fy, 457.296);
  EXPECT_DOUBLE_EQ(reader.camera().cx, 367.215);
  EXPECT_DOUBLE_EQ(reader.camera().cy, 248.375);
  EXPECT_DOUBLE_EQ(reader.imuNoise().gyro_noise_density, 1.6968e-04);
  EXPECT_FALSE(reader.hasGroundTruth());  // micro has no state_groundtruth_estimate0/data.csv

  size_t frames = 0, imu = 0, imu_since_frame = 0;
  int64_t last_t = INT64_MIN, last_imu_t = INT64_MIN, first_frame_t = 0;
  Measurement m;
  std::vector<Measurement::Type> first_two;
  while (reader.next(m)) {
    ASSERT_GE(m.timeNs(), last_t) << "timestamps went backwards";
    last_t = m.timeNs();
    if (first_two.size() < 2) first_two.push_back(m.type);
    if (m.isImu()) {
      ++imu;
      ++imu_since_frame;
      last_imu_t = m.imu.t_ns;
      ASSERT_TRUE(m.frame.image.empty());
    } else {
      if (frames == 0) first_frame_t = m.frame.t_ns;
      if (frames > 0) {  // 20 Hz camera, 200 Hz IMU: 10 samples between frames
        EXPECT_NEAR(static_cast<double>(imu_since_frame), 10.0, 1.0) << "frame " << frames;
      }
      EXPECT_LE(last_imu_t, m.frame.t_ns);
      ASSERT_EQ(m.frame.image.type(), CV_8UC1);
      ASSERT_EQ(m.frame.image.cols, 752);
      ASSERT_EQ(m.frame.image.rows, 480);
      imu_since_frame = 0;
      ++frames;
    }
  }
  EXPECT_EQ(frames, 95u);
  EXPECT_EQ(imu, 29120u);
  EXPECT_EQ(reader.skippedFrames(), 0u);
  // The first image and the first IMU row share a timestamp: the IMU sample comes first.
  EXPECT_EQ(first_frame_t, 1403715273262142976);
  ASSERT_EQ(first_two.size(), 2u);
  EXPECT_EQ(first_two[0], Measurement::Type::kImu);
  EXPECT_EQ(first_two[1], Measurement::Type::kFrame);
}

TEST(EurocReader, AcceptsMav0AsRootWithoutLoadingImages) {
  fs::path mav = adugs::test::sharedDataDir() / "euroc_v101_micro" / "mav0";
  ADUGS_REQUIRE_SHARED(mav);
  EurocReader reader(mav.string(), EurocReaderOptions{false, false});
  Measurement m;
  size_t frames = 0;
  while (reader.next(m)) {
    if (!m.isFrame()) continue;
    EXPECT_TRUE(m.frame.image.empty());
    EXPECT_TRUE(fs::exists(m.frame.path)) << m.frame.path;
    ++frames;
  }
  EXPECT_EQ(frames, 95u);
}

TEST(EurocReader, InterleavesSyntheticStreamsImuFirstOnTies) {
  Sequence s(3, 8);  // frames 1000 1100 1200; IMU 1000 1050 ... 1350
  std::vector<Measurement> ms = readAll(s.dir.path().string());
  std::string order;
  for (const Measurement& m : ms) order += m.isImu() ? 'i' : 'F';
  EXPECT_EQ(order, "iFiiFiiFiii");
  EXPECT_EQ(ms[1].frame.t_ns, 1000);
  EXPECT_EQ(ms[1].frame.image.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(ms[4].frame.image.at<uint8_t>(5, 5), 10);
  EXPECT_EQ(ms[0].imu.gyro.z(), 0.03);
  EXPECT_EQ(ms[0].imu.accel.x(), 9.81);
  EXPECT_EQ(ms[10].imu.t_ns, 1350);
}

TEST(EurocReader, ReportsGroundTruthWhenPresent) {
  Sequence s;
  EXPECT_FALSE(EurocReader(s.dir.path().string()).hasGroundTruth());
  fs::path gt = s.mav() / "state_groundtruth_estimate0" / "data.csv";
  writeText(gt, "#t\n");
  EurocReader reader(s.mav().string());
  EXPECT_TRUE(reader.hasGroundTruth());
  EXPECT_EQ(reader.groundTruthPath(), gt.string());
}

TEST(EurocReader, MissingFoldersAndFilesAreNamed) {
  TempDir empty;
  fs::path nowhere = empty / "nowhere";
  expectLocated(errorReading(nowhere.string()), nowhere, 0, "", "folder not found");
  expectLocated(errorReading(empty.path().string()), empty.path(), 0, "", "not an EuRoC ASL sequence");

  Sequence a;
  fs::remove_all(a.mav() / "imu0");
  expectLocated(errorReading(a.dir.path().string()), a.mav() / "imu0", 0, "", "folder not found");
  Sequence b;
  fs::remove(b.mav() / "cam0" / "sensor.yaml");
  expectLocated(errorReading(b.dir.path().string()), b.mav() / "cam0" / "sensor.yaml", 0, "", "file not found");
  Sequence c;
  fs::remove(c.camCsv());
  expectLocated(errorReading(c.dir.path().string()), c.camCsv(), 0, "", "file not found");
  Sequence d;
  fs::remove_all(d.mav() / "cam0" / "data");
  expectLocated(errorReading(d.dir.path().string()), d.mav() / "cam0" / "data", 0, "", "folder not found");
}

TEST(EurocReader, BadSensorYamlIsNamed) {
  Sequence s;
  fs::path yaml = s.mav() / "imu0" / "sensor.yaml";
  writeText(yaml, "rate_hz: 200\n");
  expectLocated(errorReading(s.dir.path().string()), yaml, 1, "gyroscope_noise_density", "missing required key");
}

TEST(EurocReader, MissingImageIsAnErrorOrSkipped) {
  Sequence s;
  fs::remove(s.image(2));
  expectLocated(errorReading(s.dir.path().string()), s.camCsv(), 4, "filename", "1200.png' is missing");

  testing::internal::CaptureStderr();
  std::vector<Measurement> ms = readAll(s.dir.path().string(), EurocReaderOptions{true, true});
  std::string warnings = testing::internal::GetCapturedStderr();
  EXPECT_EQ(countFrames(ms), 3u);
  EXPECT_NE(warnings.find("warning:"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("1200.png"), std::string::npos) << warnings;
  for (const Measurement& m : ms) EXPECT_NE(m.frame.t_ns, 1200);
  EurocReader reader(s.dir.path().string(), EurocReaderOptions{true, true});
  Measurement m;
  testing::internal::CaptureStderr();
  while (reader.next(m)) {
  }
  testing::internal::GetCapturedStderr();
  EXPECT_EQ(reader.skippedFrames(), 1u);
}

TEST(EurocReader, MissingImageIsFoundEvenWithoutLoadingImages) {
  Sequence s;
  fs::remove(s.image(0));
  expectLocated(errorReading(s.dir.path().string(), EurocReaderOptions{false, false}), s.camCsv(), 2, "filename",
                "is missing");
}

TEST(EurocReader, CorruptPngIsAnErrorOrSkipped) {
  Sequence s;
  writeText(s.image(1), "\x89PNG\r\n\x1a\n this is not really a PNG");
  expectLocated(errorReading(s.dir.path().string()), s.camCsv(), 3, "filename", "cannot be decoded");
  testing::internal::CaptureStderr();
  EurocReader reader(s.dir.path().string(), EurocReaderOptions{true, true});
  Measurement m;
  size_t frames = 0;
  while (reader.next(m)) frames += m.isFrame();
  std::string warnings = testing::internal::GetCapturedStderr();
  EXPECT_EQ(frames, 3u);
  EXPECT_EQ(reader.skippedFrames(), 1u);
  EXPECT_NE(warnings.find("1100.png"), std::string::npos) << warnings;
}

TEST(EurocReader, WrongImageSizeIsNeverSkipped) {
  Sequence s;
  cv::imwrite(s.image(3).string(), cv::Mat(kHeight, kWidth + 1, CV_8UC1, cv::Scalar(0)));
  expectLocated(errorReading(s.dir.path().string()), s.camCsv(), 5, "filename", "is 33x24 but cam0/sensor.yaml");
  expectLocated(errorReading(s.dir.path().string(), EurocReaderOptions{true, true}), s.camCsv(), 5, "filename",
                "33x24");
}

TEST(EurocReader, ColourImagesAreConvertedToGray) {
  Sequence s;
  cv::imwrite(s.image(0).string(), cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(50, 50, 50)));
  std::vector<Measurement> ms = readAll(s.dir.path().string());
  ASSERT_TRUE(ms[1].isFrame());
  EXPECT_EQ(ms[1].frame.image.type(), CV_8UC1);
  EXPECT_EQ(ms[1].frame.image.at<uint8_t>(0, 0), 50);
}

TEST(EurocReader, MalformedCsvLinesAreNamed) {
  Sequence a;
  Sequence::setLine(a.imuCsv(), 5, "1150,0.01,0.02,0.03,9.81");  // truncated
  expectLocated(errorReading(a.dir.path().string()), a.imuCsv(), 5, "", "expected 7 fields, found 5");

  Sequence b;
  Sequence::setLine(b.imuCsv(), 3, "1050,0.01,0.02,0.03,9.81,abc,-0.1");
  expectLocated(errorReading(b.dir.path().string()), b.imuCsv(), 3, "a_y", "not a number: 'abc'");

  Sequence c;
  Sequence::setLine(c.camCsv(), 3, "11x0,1100.png");
  expectLocated(errorReading(c.dir.path().string()), c.camCsv(), 3, "timestamp", "not an integer");

  Sequence d;
  Sequence::setLine(d.camCsv(), 4, "1200,1200.png,extra");
  expectLocated(errorReading(d.dir.path().string(), EurocReaderOptions{true, true}), d.camCsv(), 4, "",
                "expected 2 fields");

  Sequence e;
  Sequence::setLine(e.camCsv(), 2, "1000,");
  expectLocated(errorReading(e.dir.path().string()), e.camCsv(), 2, "filename", "empty file name");
}

TEST(EurocReader, NonFiniteImuValuesAreNeverSkipped) {
  for (std::string bad : {"nan", "inf", "-inf", "1e999"}) {
    Sequence s;
    Sequence::setLine(s.imuCsv(), 6, "1200,0.01,0.02,0.03,9.81," + bad + ",-0.1");
    expectLocated(errorReading(s.dir.path().string(), EurocReaderOptions{true, true}), s.imuCsv(), 6, "a_y", bad);
  }
}

TEST(EurocReader, NonMonotonicOrDuplicateTimestampsAreErrors) {
  Sequence a;
  Sequence::setLine(a.imuCsv(), 4, Sequence::imuRow(1050).substr(0, Sequence::imuRow(1050).size() - 1));
  expectLocated(errorReading(a.dir.path().string()), a.imuCsv(), 4, "timestamp",
                "duplicate timestamp 1050 is not after 1050 on line 3");

  Sequence b;
  Sequence::setLine(b.imuCsv(), 6, "1020,0,0,0,0,0,0");
  expectLocated(errorReading(b.dir.path().string(), EurocReaderOptions{true, true}), b.imuCsv(), 6, "timestamp",
                "goes backwards");

  Sequence c;
  Sequence::setLine(c.camCsv(), 4, "1100,1100.png");
  expectLocated(errorReading(c.dir.path().string(), EurocReaderOptions{true, true}), c.camCsv(), 4, "timestamp",
                "duplicate timestamp 1100");

  Sequence d;
  Sequence::setLine(d.camCsv(), 5, "900,1000.png");
  expectLocated(errorReading(d.dir.path().string()), d.camCsv(), 5, "timestamp", "goes backwards");
}

TEST(EurocReader, ErrorsAreStickyAndNoSampleIsReturnedAfterThem) {
  Sequence s;
  Sequence::setLine(s.imuCsv(), 4, "1100,0.5,0.5,0.5,0.5,bad,0.5");  // the third IMU row
  EurocReader reader(s.dir.path().string());
  Measurement m;
  std::vector<int64_t> times;
  std::string first;
  try {
    while (reader.next(m)) times.push_back(m.timeNs());
  } catch (const InputError& e) {
    first = e.what();
  }
  EXPECT_NE(first.find(":4: field 'a_y'"), std::string::npos) << first;
  // The error came while fetching the row after IMU 1050; nothing read past it is ever returned.
  EXPECT_EQ(times, (std::vector<int64_t>{1000, 1000, 1050}));
  try {
    reader.next(m);
    FAIL() << "next() returned after an error";
  } catch (const InputError& e) {
    EXPECT_EQ(first, e.what());
  }
}

TEST(EurocReader, BadRowAfterSkippedFrameStopsTheStreamThere) {
  Sequence s(4, 8);
  fs::remove(s.image(1));                              // frame 1100: skipped
  Sequence::setLine(s.camCsv(), 4, "12x0,1200.png");  // the row after it is malformed
  testing::internal::CaptureStderr();
  EurocReader reader(s.dir.path().string(), EurocReaderOptions{true, true});
  Measurement m;
  std::vector<int64_t> times;
  std::optional<InputError> err;
  try {
    while (reader.next(m)) times.push_back(m.timeNs());
  } catch (const InputError& e) {
    err = e;
  }
  testing::internal::GetCapturedStderr();
  expectLocated(err, s.camCsv(), 4, "timestamp", "not an integer");
  EXPECT_EQ(times, (std::vector<int64_t>{1000, 1000, 1050, 1100}));
}

TEST(EurocReader, RootThatIsAFileIsNamed) {
  Sequence s;
  expectLocated(errorReading(s.camCsv().string()), s.camCsv(), 0, "", "is not a folder");
}

TEST(EurocReader, EmptySequencesAreErrors) {
  Sequence a(0, 8);
  expectLocated(errorReading(a.dir.path().string()), a.camCsv(), 0, "", "no frames");
  Sequence b(3, 0);
  expectLocated(errorReading(b.dir.path().string()), b.imuCsv(), 0, "", "no IMU samples");

  Sequence c(2, 8);  // every frame bad: skipping cannot produce an empty camera stream
  fs::remove(c.image(0));
  fs::remove(c.image(1));
  testing::internal::CaptureStderr();
  auto err = errorReading(c.dir.path().string(), EurocReaderOptions{true, true});
  testing::internal::GetCapturedStderr();
  expectLocated(err, c.camCsv(), 0, "", "no usable frames: all 2 were skipped");
}

}  // namespace
}  // namespace adugs::data

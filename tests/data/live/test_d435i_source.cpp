// The D435i source end to end on the simulated camera (fake sysfs tree, FIFOs, fake V4L2, device
// thread in real time): one time-ordered stream of frames and united IMU samples on one clock,
// units and axes, the device's controls, and every way it ends (unplugged camera or IMU, stop
// request) or refuses to start.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include <linux/videodev2.h>

#include "data/device/realsense_imu.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "data/sources/d435i_source.h"
#include "data/sources/visp_realsense2_source.h"
#include "tests/data/live/fake_d435i.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

struct Stream {
  std::vector<data::Measurement> all;
  bool ended = false;  // next() returned false
};

// Reads until `seconds` of host time passed or the source ends.
Stream collect(data::D435iSource& source, double seconds) {
  Stream s;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  data::Measurement m;
  while (std::chrono::steady_clock::now() < until) {
    if (!source.next(m)) {
      s.ended = true;
      break;
    }
    s.all.push_back(m);
  }
  return s;
}

// What the fake's samples encode (fake_d435i.h).
int64_t gyroIndex(const data::ImuSample& s, double lsb_deg) {
  return std::llround(-s.gyro.x() / (lsb_deg * M_PI / 180.0));  // raw x = k, camera x = -raw x
}
int frameIndex(const cv::Mat& image) { return image.at<uint8_t>(0, 0) + 256 * image.at<uint8_t>(0, 1); }

// Checks order, IMU continuity, units, frames, and that both streams share one clock; returns the
// number of frames.
size_t checkStream(const Stream& s, const test::FakeD435i& fake, double gyro_lsb_deg, double settle_s = 0.5) {
  const int64_t t0 = fake.deviceStartUs();
  int64_t prev_t = INT64_MIN;
  bool prev_frame = false;
  int64_t prev_k = -1;
  size_t frames = 0, imu = 0;
  double imu_offset_min = 1e18, imu_offset_max = -1e18;
  std::vector<std::pair<int64_t, double>> frame_offsets;  // (stamp, stamp - truth)
  const int64_t first_t = s.all.empty() ? 0 : s.all.front().timeNs();
  for (const data::Measurement& m : s.all) {
    const int64_t t = m.timeNs();
    EXPECT_GE(t, prev_t) << "out of order";
    if (t == prev_t) {
      EXPECT_FALSE(prev_frame && m.isImu()) << "IMU after a frame with the same stamp";
    }
    prev_t = t;
    prev_frame = m.isFrame();
    if (m.isImu()) {
      ++imu;
      const int64_t k = gyroIndex(m.imu, gyro_lsb_deg);
      if (prev_k >= 0) {
        EXPECT_EQ(k, prev_k + 1) << "an IMU sample went missing";
      }
      prev_k = k;
      // The accelerometer interpolated at the gyro stamp: raw x = j at device time 4000 j us, so
      // 2500 k / 4000 at the gyro's; raw z = -1000 (-1 g): +g on the camera's z.
      EXPECT_NEAR(m.imu.accel.x(), -(2500.0 * k / 4000.0) * data::kRealsenseAccelLsb, 1e-9);
      EXPECT_NEAR(m.imu.accel.y(), 0.0, 1e-12);
      EXPECT_NEAR(m.imu.accel.z(), data::kStandardGravity, 1e-12);
      EXPECT_NEAR(m.imu.gyro.y(), 300 * gyro_lsb_deg * M_PI / 180.0, 1e-12);
      EXPECT_NEAR(m.imu.gyro.z(), 450 * gyro_lsb_deg * M_PI / 180.0, 1e-12);
      const double offset = static_cast<double>(t) - fake.hostNsOfDeviceUs(t0 + 2500 * k);
      if (t - first_t > settle_s * 1e9) {
        imu_offset_min = std::min(imu_offset_min, offset);
        imu_offset_max = std::max(imu_offset_max, offset);
      }
    } else {
      ++frames;
      const cv::Mat& im = m.frame.image;
      EXPECT_EQ(im.type(), CV_8UC1);
      EXPECT_EQ(im.cols, 848);
      EXPECT_EQ(im.rows, 480);
      EXPECT_EQ(im.at<uint8_t>(240, 400), 100) << "not the left image";
      const int f = frameIndex(im);
      frame_offsets.push_back({t, static_cast<double>(t) - fake.hostNsOfDeviceUs(t0 + 10000 + 33333LL * f)});
    }
  }
  EXPECT_GT(imu, 0u);
  EXPECT_GT(frames, 0u);
  // Host stamp minus the true host time of the event: a constant (the smallest latency seen) up to
  // the clock fit's error, the same for IMU and frames (one clock).
  EXPECT_LT(imu_offset_max - imu_offset_min, 500e3) << "IMU stamps wander by more than 0.5 ms";
  EXPECT_GT(imu_offset_min, -0.2e6);
  EXPECT_LT(imu_offset_max, 20e6);
  for (const auto& [t, offset] : frame_offsets) {
    if (t - first_t <= settle_s * 1e9) continue;
    EXPECT_GT(offset, imu_offset_min - 0.2e6) << "frame and IMU on different clocks";
    EXPECT_LT(offset, imu_offset_max + 0.2e6) << "frame and IMU on different clocks";
  }
  return frames;
}

TEST(D435iSource, OneTimeOrderedStreamOnTheDeviceClock) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iOptions o = fake.options();
  o.format = "y8i";  // both imagers: the left one must come out
  {
    data::D435iSource source(o, fake.v4l2());
    EXPECT_NE(source.description().find("843112071234"), std::string::npos) << source.description();
    EXPECT_NE(source.description().find("Y8I"), std::string::npos) << source.description();
    const std::string node = fake.devRoot() + "/video0";
    EXPECT_EQ(fake.v4l2().state(node).fourcc, v4l2_fourcc('Y', '8', 'I', ' '));
    EXPECT_EQ(fake.v4l2().state(node).fps, 30.0);
    EXPECT_EQ(fake.v4l2().state(node).xu.at(2), (std::vector<uint8_t>{0}));     // emitter off
    EXPECT_EQ(fake.v4l2().state(node).xu.at(0x0B), (std::vector<uint8_t>{1}));  // auto exposure
    EXPECT_EQ(fake.v4l2().state(fake.devRoot() + "/video1").meta_format, v4l2_fourcc('D', '4', 'X', 'X'));
    EXPECT_EQ(test::readFirstLine(fake.iioDir("accel_3d") / "in_accel_sampling_frequency"), "250");
    EXPECT_EQ(test::readFirstLine(fake.iioDir("gyro_3d") / "in_anglvel_sampling_frequency"), "400");
    EXPECT_EQ(test::readFirstLine(fake.iioDir("gyro_3d") / "buffer/enable"), "1");
    fake.start();
    const Stream s = collect(source, 2.5);  // the device counter wraps 1.5 s in
    fake.stop();
    EXPECT_FALSE(s.ended);
    const size_t frames = checkStream(s, fake, 0.1);
    EXPECT_GE(frames, 50u);  // 30 Hz, after the 0.5 s clock warm-up
    const data::D435iStats st = source.stats();
    EXPECT_TRUE(st.device_clock);
    EXPECT_TRUE(st.imu_device_stamps);
    EXPECT_EQ(st.frames_lost_by_driver, 0u);
    EXPECT_EQ(st.frames_late, 0u);
    EXPECT_EQ(st.imu_late, 0u);
    EXPECT_EQ(st.imu_out_of_order, 0u);
  }
  // Closed: streaming off, the emitter back as it was.
  EXPECT_EQ(test::readFirstLine(fake.iioDir("gyro_3d") / "buffer/enable"), "0");
  EXPECT_FALSE(fake.v4l2().state(fake.devRoot() + "/video0").streaming);
  EXPECT_EQ(fake.v4l2().state(fake.devRoot() + "/video0").xu.at(2), (std::vector<uint8_t>{1}));
}

TEST(D435iSource, FirmwareWith32BitGyroDataAndGreyFrames) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.gyro_bits = 32;
  config.accel_bits = 32;
  test::FakeD435i fake(dir.path(), config);
  data::D435iOptions o = fake.options();
  o.exposure_us = 5000;  // manual
  o.gain = 32;
  data::D435iSource source(o, fake.v4l2());
  const std::string node = fake.devRoot() + "/video0";
  EXPECT_EQ(fake.v4l2().state(node).fourcc, v4l2_fourcc('G', 'R', 'E', 'Y'));  // auto: GREY first
  EXPECT_EQ(fake.v4l2().state(node).xu.at(0x0B), (std::vector<uint8_t>{0}));
  EXPECT_EQ(fake.v4l2().state(node).xu.at(3), (std::vector<uint8_t>{0x88, 0x13, 0, 0}));  // 5000 us
  EXPECT_EQ(fake.v4l2().state(node).controls.at(V4L2_CID_GAIN), 32);
  fake.start();
  const Stream s = collect(source, 1.5);
  fake.stop();
  checkStream(s, fake, 0.0001);  // 0.0001 deg/s per LSB
}

TEST(D435iSource, ColourStreamGivesGreyAndBgrImages) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iOptions o = fake.options();
  o.stream = "color";
  data::D435iSource source(o, fake.v4l2());
  EXPECT_EQ(fake.v4l2().state(fake.devRoot() + "/video2").fourcc, v4l2_fourcc('Y', 'U', 'Y', 'V'));
  EXPECT_TRUE(fake.v4l2().state(fake.devRoot() + "/video3").streaming);  // its metadata node
  EXPECT_FALSE(fake.v4l2().state(fake.devRoot() + "/video0").streaming);
  EXPECT_EQ(fake.v4l2().state(fake.devRoot() + "/video2").controls.at(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_APERTURE_PRIORITY);
  fake.start();
  const Stream s = collect(source, 1.5);
  fake.stop();
  size_t frames = 0;
  for (const data::Measurement& m : s.all) {
    if (!m.isFrame()) continue;
    ++frames;
    EXPECT_EQ(m.frame.image.at<uint8_t>(100, 100), 100);  // the luma
    ASSERT_EQ(m.frame.colour.type(), CV_8UC3);
    EXPECT_EQ(m.frame.colour.at<cv::Vec3b>(100, 100), cv::Vec3b(98, 98, 98));  // BT.601 grey of luma 100
  }
  EXPECT_GE(frames, 20u);
  checkStream(s, fake, 0.1);
}

TEST(D435iSource, UnpluggedCameraEndsTheStreamWithAMessage) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iSource source(fake.options(), fake.v4l2());
  fake.start();
  Stream before = collect(source, 1.0);
  EXPECT_FALSE(before.ended);
  fake.unplugCamera();
  const Stream after = collect(source, 30.0);  // a hang guard, not a timing bound
  EXPECT_TRUE(after.ended) << "the stream did not end within 30 s of the unplug";
  fake.stop();
  EXPECT_NE(source.stopReason().find("video"), std::string::npos) << source.stopReason();
  EXPECT_NE(source.stopReason().find("unplugged"), std::string::npos) << source.stopReason();
  before.all.insert(before.all.end(), after.all.begin(), after.all.end());
  checkStream(before, fake, 0.1);  // what came before the end is whole and in order
  data::Measurement m;
  EXPECT_FALSE(source.next(m));  // and it stays ended
}

TEST(D435iSource, ImuGoneEndsTheStreamWithAMessage) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iSource source(fake.options(), fake.v4l2());
  fake.start();
  collect(source, 0.5);
  fake.unplugImu();
  const Stream after = collect(source, 5.0);
  fake.stop();
  EXPECT_TRUE(after.ended);
  EXPECT_NE(source.stopReason().find("iio:device"), std::string::npos) << source.stopReason();
  EXPECT_NE(source.stopReason().find("closed"), std::string::npos) << source.stopReason();
}

TEST(D435iSource, StopWakesABlockedNext) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iSource source(fake.options(), fake.v4l2());  // the device never starts: next() blocks
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    source.stop();
  });
  data::Measurement m;
  EXPECT_FALSE(source.next(m));
  stopper.join();
  // stop() is what ended it: otherwise only the stall timeout could ("no frame for ...").
  EXPECT_EQ(source.stopReason(), "stopped on request");
}

TEST(D435iSource, AStalledCameraEndsTheStream) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iOptions o = fake.options();
  o.stall_timeout_s = 0.5;
  data::D435iSource source(o, fake.v4l2());  // never started
  data::Measurement m;
  EXPECT_FALSE(source.next(m));
  EXPECT_NE(source.stopReason().find("no frame"), std::string::npos) << source.stopReason();
}

TEST(D435iSource, ASlowConsumerLosesFramesNeverImuSamples) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  data::D435iOptions o = fake.options();
  o.buffers = 4;
  data::D435iSource source(o, fake.v4l2());
  fake.start();
  Stream s = collect(source, 0.5);
  // The consumer is busy while the camera delivers 24 frames into its 4 buffers (waited for by
  // the device's own count, whatever the machine's load; 30 s is only a hang guard).
  const int delivered = fake.framesDelivered();
  const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (fake.framesDelivered() < delivered + 24 && std::chrono::steady_clock::now() < guard)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_GE(fake.framesDelivered(), delivered + 24) << "the fake camera stopped delivering";
  const Stream rest = collect(source, 1.0);
  fake.stop();
  s.all.insert(s.all.end(), rest.all.begin(), rest.all.end());
  checkStream(s, fake, 0.1);  // includes: no IMU sample missing
  // 24 frames for 4 buffers: at least 20 lost, less one the consumer may have taken as it stopped
  // and a few in flight: 15.
  EXPECT_GE(source.stats().frames_lost_by_driver, 15u);
  EXPECT_GE(source.counts().frames_lost, source.stats().frames_lost_by_driver);
  EXPECT_TRUE(source.isLive());
}

TEST(D435iSource, WithoutMetadataFramesKeepTheDriversHostStamps) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.metadata_node = false;
  test::FakeD435i fake(dir.path(), config);
  data::D435iSource source(fake.options(), fake.v4l2());
  fake.start();
  const Stream s = collect(source, 1.5);
  fake.stop();
  EXPECT_FALSE(source.stats().device_clock);
  int64_t prev = INT64_MIN;
  size_t frames = 0;
  for (const data::Measurement& m : s.all) {
    EXPECT_GE(m.timeNs(), prev);
    prev = m.timeNs();
    if (!m.isFrame()) continue;
    ++frames;
    // Stamped at the first packet's arrival: 0.3 ms after the readout started.
    const int f = frameIndex(m.frame.image);
    const double arrival = fake.hostNsOfDeviceUs(fake.deviceStartUs() + 10000 + 33333LL * f + 4000) + 300e3;
    EXPECT_NEAR(static_cast<double>(m.timeNs()), arrival, 1e3);
  }
  EXPECT_GE(frames, 25u);
}

TEST(D435iSource, ASilentMetadataNodeFallsBackToTheDriversStamps) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.metadata_silent = true;  // a kernel whose metadata node never delivers: frames must still come
  test::FakeD435i fake(dir.path(), config);
  data::D435iSource source(fake.options(), fake.v4l2());
  EXPECT_TRUE(source.stats().device_clock);  // it had a metadata node
  fake.start();
  const Stream s = collect(source, 2.5);
  fake.stop();
  EXPECT_FALSE(source.stats().device_clock);  // ... and gave up on it after 30 frames
  size_t frames = 0;
  for (const data::Measurement& m : s.all) frames += m.isFrame();
  EXPECT_GE(frames, 25u);
  EXPECT_GE(source.stats().frames_without_metadata, 30u);
}

TEST(D435iSource, PlainUvcMetadataStampsFramesAtReadoutStart) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.d4xx_metadata = false;
  test::FakeD435i fake(dir.path(), config);
  data::D435iSource source(fake.options(), fake.v4l2());
  fake.start();
  const Stream s = collect(source, 1.5);
  fake.stop();
  // Frames stamped 4 ms (half the exposure) later than mid-exposure, on the device clock.
  double imu_offset = 0;
  for (const data::Measurement& m : s.all) {
    if (m.isImu()) imu_offset = static_cast<double>(m.timeNs()) - fake.hostNsOfDeviceUs(fake.deviceStartUs() + 2500 * gyroIndex(m.imu, 0.1));
  }
  size_t frames = 0;
  for (const data::Measurement& m : s.all) {
    if (!m.isFrame() || m.timeNs() - s.all.front().timeNs() < 500'000'000) continue;
    ++frames;
    const int f = frameIndex(m.frame.image);
    const double readout = fake.hostNsOfDeviceUs(fake.deviceStartUs() + 10000 + 33333LL * f + 4000);
    EXPECT_NEAR(static_cast<double>(m.timeNs()) - readout, imu_offset, 0.3e6);
  }
  EXPECT_GE(frames, 10u);
}

TEST(D435iSource, HostStampedImuRecordsStillComeInOrder) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.imu_device_stamps = false;  // a kernel that stamps records itself (CLOCK_REALTIME)
  test::FakeD435i fake(dir.path(), config);
  data::D435iSource source(fake.options(), fake.v4l2());
  fake.start();
  const Stream s = collect(source, 1.5);
  fake.stop();
  EXPECT_FALSE(source.stats().imu_device_stamps);
  int64_t prev = INT64_MIN;
  size_t imu = 0;
  for (const data::Measurement& m : s.all) {
    EXPECT_GE(m.timeNs(), prev);
    prev = m.timeNs();
    if (!m.isImu()) continue;
    ++imu;
    // Host stamps turned into CLOCK_MONOTONIC: the true sample time, to a microsecond.
    const double truth = fake.hostNsOfDeviceUs(fake.deviceStartUs() + 2500 * gyroIndex(m.imu, 0.1));
    EXPECT_NEAR(static_cast<double>(m.timeNs()), truth, 20e3);
  }
  EXPECT_GE(imu, 300u);
}

TEST(D435iSource, RefusesWhatTheCameraCannotDo) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  auto expectError = [&](data::D435iOptions o, const std::string& needle) {
    try {
      data::D435iSource source(o, fake.v4l2());
      ADD_FAILURE() << "opened with " << needle;
    } catch (const data::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  data::D435iOptions o = fake.options();
  o.usb_id = "8086:0b07";  // a D435 (no IMU) is not there
  expectError(o, "no USB camera 8086:0b07");
  o = fake.options();
  o.serial = "000000000000";
  expectError(o, "843112071234");  // names the serial that is there
  o = fake.options();
  o.width = 1024;
  o.height = 768;
  expectError(o, "848x480 (6/15/30/60/90 Hz)");  // lists what is offered
  o = fake.options();
  o.fps = 90;
  o.width = 1280;
  o.height = 720;
  expectError(o, "1280x720 at 90 Hz");
  test::writeText(fake.iioDir("gyro_3d") / "scan_elements/in_anglvel_y_type", "le:s16\n");  // a broken IMU
  expectError(fake.options(), "in_anglvel_y_type");
  // Nothing was left streaming by the failed attempts, and the emitter was not touched.
  EXPECT_FALSE(fake.v4l2().state(fake.devRoot() + "/video0").streaming);
  EXPECT_EQ(fake.v4l2().state(fake.devRoot() + "/video0").xu.at(2), (std::vector<uint8_t>{1}));
  EXPECT_EQ(test::readFirstLine(fake.iioDir("accel_3d") / "buffer/enable"), "0");
}

TEST(D435iSource, OpenedWithCalibrationFromKalibrFilesOrTheConfig) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  {
    data::OpenedSequence seq = data::openD435i(fake.options(), {}, fake.v4l2());
    EXPECT_EQ(seq.camera.width, 848);
    EXPECT_EQ(seq.camera.fx, 426.0);
    EXPECT_NEAR(seq.camera.T_B_C.translation().z(), 0.01174, 1e-12);
    EXPECT_EQ(seq.imu_noise.gyro_noise_density, 0.005);
    EXPECT_NE(seq.calibration_from.find("placeholder"), std::string::npos);
  }
  test::writeText(dir.path() / "camchain.yaml",
                  "cam0:\n  camera_model: pinhole\n  intrinsics: [430, 431, 420, 241]\n  distortion_model: radtan\n"
                  "  distortion_coeffs: [0.01, 0, 0, 0]\n  resolution: [640, 480]\n  timeshift_cam_imu: 0.004\n");
  try {
    data::openD435i(fake.options(), {(dir.path() / "camchain.yaml").string()}, fake.v4l2());
    FAIL() << "accepted a 640x480 calibration for an 848x480 stream";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camchain.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("resolution"), std::string::npos) << e.what();
  }
  data::D435iOptions o = fake.options();
  o.width = 640;
  data::OpenedSequence seq = data::openD435i(o, {(dir.path() / "camchain.yaml").string()}, fake.v4l2());
  EXPECT_EQ(seq.camera.fx, 430.0);
  EXPECT_NE(seq.calibration_from.find("camchain.yaml"), std::string::npos);
  seq.source.reset();
  if (!data::vispRealSense2Available()) {  // Debian's ViSP: the librealsense backend says why it is not there
    o.backend = "librealsense";
    try {
      data::openD435i(o, {(dir.path() / "camchain.yaml").string()}, fake.v4l2());
      FAIL() << "opened the librealsense backend in a build without it";
    } catch (const data::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("VISP_HAVE_REALSENSE2"), std::string::npos) << e.what();
    }
  }
}

TEST(D435iOptions, TheConfigFileHoldsTheDefaultsInCode) {
  // data/config/d435i.yaml says "the defaults in code are these values": check it.
  data::YamlOptionsReader root = data::YamlOptionsReader::fromFile(std::string(ADUGS_SOURCE_DIR) + "/data/config/d435i.yaml");
  data::YamlOptionsReader r = root.child("d435i", true);
  data::D435iOptions file;
  file.width = 1;  // every key must be in the file for this to come back
  file.camera.camera.fx = 0;
  file.imu_noise.gyro_noise_density = 0;
  data::readD435iOptions(r, &file);
  r.finish();
  const data::D435iOptions code;
  EXPECT_EQ(file.backend, code.backend);
  EXPECT_EQ(file.stream, code.stream);
  EXPECT_EQ(file.format, code.format);
  EXPECT_EQ(file.width, code.width);
  EXPECT_EQ(file.height, code.height);
  EXPECT_EQ(file.fps, code.fps);
  EXPECT_EQ(file.buffers, code.buffers);
  EXPECT_EQ(file.metadata, code.metadata);
  EXPECT_EQ(file.emitter, code.emitter);
  EXPECT_EQ(file.exposure_us, code.exposure_us);
  EXPECT_EQ(file.gain, code.gain);
  EXPECT_EQ(file.imu, code.imu);
  EXPECT_EQ(file.accel_hz, code.accel_hz);
  EXPECT_EQ(file.gyro_hz, code.gyro_hz);
  EXPECT_EQ(file.gyro_lsb_deg_s, code.gyro_lsb_deg_s);
  EXPECT_EQ(file.iio_buffer_records, code.iio_buffer_records);
  EXPECT_EQ(file.frame_latency_s, code.frame_latency_s);
  EXPECT_EQ(file.imu_latency_s, code.imu_latency_s);
  EXPECT_EQ(file.stall_timeout_s, code.stall_timeout_s);
  EXPECT_EQ(file.clock_warmup_s, code.clock_warmup_s);
  const data::CameraCalibration &a = file.camera.camera, &b = code.camera.camera;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.fy, b.fy);
  EXPECT_EQ(a.cx, b.cx);
  EXPECT_EQ(a.cy, b.cy);
  EXPECT_EQ(a.distortion, b.distortion);
  EXPECT_TRUE(a.T_B_C.isApprox(b.T_B_C, 1e-12)) << a.T_B_C.matrix() << "\n" << b.T_B_C.matrix();
  EXPECT_EQ(file.camera.time_offset_s, code.camera.time_offset_s);
  EXPECT_EQ(file.imu_noise.accel_noise_density, code.imu_noise.accel_noise_density);
  EXPECT_EQ(file.imu_noise.accel_random_walk, code.imu_noise.accel_random_walk);
  EXPECT_EQ(file.imu_noise.gyro_noise_density, code.imu_noise.gyro_noise_density);
  EXPECT_EQ(file.imu_noise.gyro_random_walk, code.imu_noise.gyro_random_walk);
  EXPECT_EQ(file.imu_noise.rate_hz, code.imu_noise.rate_hz);
}

}  // namespace
}  // namespace adugs::data

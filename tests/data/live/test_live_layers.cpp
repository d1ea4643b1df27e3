// The layers under the D435i source, each on the fake kernel: sysfs discovery by USB id, one V4L2
// node (negotiation, streaming, unplug), the D4xx UVC extension-unit controls, and an IIO sensor
// (scan elements, rate, buffer, records through a FIFO, the device going away).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <unistd.h>


#include "data/device/d4xx_controls.h"
#include "data/device/iio_sensor.h"
#include "data/device/usb_device_tree.h"
#include "data/device/v4l2_stream.h"
#include "data/input_error.h"
#include "tests/data/live/fake_d435i.h"
#include "tests/device_bytes.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

namespace fs = std::filesystem;

bool readable(int fd, int timeout_ms) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) == 1;
}

TEST(UsbDeviceTree, FindsTheCameraNodesByUsbIdAndNotTheLaptopsOwn) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  const std::vector<data::UsbCamera> cams = data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "8086:0B3A");
  ASSERT_EQ(cams.size(), 1u);
  const data::UsbCamera& c = cams[0];
  EXPECT_EQ(c.bus_port, "2-1");
  EXPECT_EQ(c.serial, "843112071234");
  EXPECT_EQ(c.speed, "5000");
  ASSERT_EQ(c.video.size(), 4u);  // not the webcam's video4
  EXPECT_EQ(c.video[0].name, "video0");
  EXPECT_EQ(c.video[0].dev_path, fake.devRoot() + "/video0");
  EXPECT_EQ(c.video[0].index, 0);
  EXPECT_EQ(c.video[1].index, 1);
  EXPECT_EQ(c.video[0].interface, c.video[1].interface);  // a video node and its metadata node
  EXPECT_NE(c.video[0].interface, c.video[2].interface);
  ASSERT_EQ(c.iio.size(), 2u);  // not the sensor hub's accel_3d (iio:device0)
  EXPECT_EQ(c.iio[0].name, "accel_3d");
  EXPECT_EQ(c.iio[0].dev_path, fake.devRoot() + "/iio:device1");
  EXPECT_EQ(c.iio[1].name, "gyro_3d");
  EXPECT_EQ(data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "8086").size(), 1u);
  EXPECT_EQ(data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "").size(), 2u);  // and the webcam
  EXPECT_TRUE(data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "8086:0b07").empty());
  EXPECT_TRUE(data::findUsbCameras((dir.path() / "nowhere").string(), fake.devRoot(), "").empty());
}

TEST(V4l2Stream, NegotiatesStreamsAndEndsCleanlyWhenUnplugged) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  const std::string node = fake.devRoot() + "/video0";
  try {
    data::V4l2Stream missing(fake.v4l2(), fake.devRoot() + "/video9");
    FAIL() << "opened a missing node";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("video9"), std::string::npos);
  }
  data::V4l2Stream s(fake.v4l2(), node);
  EXPECT_TRUE(s.isVideoCapture());
  EXPECT_FALSE(s.isMetaCapture());
  EXPECT_EQ(s.driver(), "uvcvideo");
  const std::vector<data::V4l2FormatInfo> formats = s.formats();
  ASSERT_EQ(formats.size(), 3u);
  EXPECT_EQ(formats[1].fourcc, v4l2_fourcc('G', 'R', 'E', 'Y'));
  ASSERT_EQ(formats[1].sizes.size(), 3u);
  EXPECT_EQ(formats[1].sizes[1].width, 848);
  EXPECT_EQ(formats[1].sizes[1].rates_hz, (std::vector<double>{6, 15, 30, 60, 90}));
  EXPECT_FALSE(s.setVideoFormat(v4l2_fourcc('G', 'R', 'E', 'Y'), 1000, 700));  // the driver gives another size
  ASSERT_TRUE(s.setVideoFormat(v4l2_fourcc('Y', '8', 'I', ' '), 848, 480));
  EXPECT_EQ(s.bytesPerLine(), 848 * 2);
  EXPECT_EQ(s.setFrameRate(30), 30.0);
  EXPECT_EQ(s.setFrameRate(50), 60.0);  // the nearest listed rate
  s.start(3);
  EXPECT_TRUE(fake.v4l2().state(node).streaming);
  EXPECT_EQ(fake.v4l2().state(node).buffers, 3u);

  data::V4l2Buffer b;
  EXPECT_FALSE(s.dequeue(&b));  // nothing yet, not gone
  EXPECT_FALSE(s.gone());
  std::vector<uint8_t> frame(848 * 480 * 2, 7);
  frame[0] = 42;
  ASSERT_TRUE(fake.v4l2().deliver(node, frame, 123'456'789'000));
  ASSERT_TRUE(readable(s.fd(), 100));
  ASSERT_TRUE(s.dequeue(&b));
  EXPECT_EQ(b.bytes, frame.size());
  EXPECT_EQ(b.data[0], 42);
  EXPECT_EQ(b.data[1], 7);
  EXPECT_EQ(b.sequence, 0u);
  EXPECT_EQ(b.timestamp_ns, 123'456'789'000);
  EXPECT_TRUE(b.monotonic);
  EXPECT_FALSE(readable(s.fd(), 0));
  // Two more buffers are queued; a third frame finds none (this one is still dequeued): lost.
  EXPECT_TRUE(fake.v4l2().deliver(node, frame, 1));
  EXPECT_TRUE(fake.v4l2().deliver(node, frame, 2));
  EXPECT_FALSE(fake.v4l2().deliver(node, frame, 3));
  s.requeue(b);
  EXPECT_TRUE(fake.v4l2().deliver(node, frame, 4));
  std::vector<uint32_t> sequences;
  while (s.dequeue(&b)) {
    sequences.push_back(b.sequence);
    s.requeue(b);
  }
  EXPECT_EQ(sequences, (std::vector<uint32_t>{1, 2, 4}));  // 3 was lost: a gap the caller counts

  fake.v4l2().unplug(node);
  EXPECT_TRUE(readable(s.fd(), 100));  // pollers wake
  EXPECT_FALSE(s.dequeue(&b));
  EXPECT_TRUE(s.gone());
  EXPECT_NE(s.message().find("video0"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("No such device"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("unplugged"), std::string::npos) << s.message();
}

TEST(V4l2Stream, MetadataNodesTakeOnlyTheirFormats) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.d4xx_metadata = false;  // a kernel whose uvcvideo knows only UVCH
  test::FakeD435i fake(dir.path(), config);
  data::V4l2Stream m(fake.v4l2(), fake.devRoot() + "/video1");
  EXPECT_TRUE(m.isMetaCapture());
  EXPECT_FALSE(m.setMetaFormat(v4l2_fourcc('D', '4', 'X', 'X')));
  EXPECT_TRUE(m.setMetaFormat(v4l2_fourcc('U', 'V', 'C', 'H')));
  m.start(4);
  EXPECT_TRUE(fake.v4l2().state(fake.devRoot() + "/video1").streaming);
}

TEST(D4xxControls, EmitterExposureAndGainThroughTheExtensionUnit) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  const std::string node = fake.devRoot() + "/video0";
  data::V4l2Stream s(fake.v4l2(), node);
  data::D4xxControls c(fake.v4l2(), s.fd(), node);
  uint8_t mode = 9;
  ASSERT_TRUE(c.readEmitter(&mode));
  EXPECT_EQ(mode, 1);  // on at power-up
  ASSERT_TRUE(c.setEmitter(0));
  EXPECT_EQ(fake.v4l2().state(node).xu.at(2), (std::vector<uint8_t>{0}));
  ASSERT_TRUE(c.setAutoExposure(false));
  ASSERT_TRUE(c.setExposureUs(0x00012345));
  EXPECT_EQ(fake.v4l2().state(node).xu.at(3), (std::vector<uint8_t>{0x45, 0x23, 0x01, 0x00}));  // little-endian
  uint32_t us = 0;
  ASSERT_TRUE(c.readExposureUs(&us));
  EXPECT_EQ(us, 0x12345u);
  bool on = true;
  ASSERT_TRUE(c.readAutoExposure(&on));
  EXPECT_FALSE(on);
  ASSERT_TRUE(c.setGain(64));
  EXPECT_EQ(fake.v4l2().state(node).controls.at(V4L2_CID_GAIN), 64);
  // The colour node's standard controls.
  std::string error;
  ASSERT_TRUE(setUvcExposure(fake.v4l2(), s.fd(), 3333, 0, &error)) << error;
  EXPECT_EQ(fake.v4l2().state(node).controls.at(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(fake.v4l2().state(node).controls.at(V4L2_CID_EXPOSURE_ABSOLUTE), 33);  // 100 us units
  // A node without the unit (the metadata node): a clear error, no crash.
  data::V4l2Stream m(fake.v4l2(), fake.devRoot() + "/video1");
  data::D4xxControls none(fake.v4l2(), m.fd(), m.path());
  EXPECT_FALSE(none.setEmitter(0));
  EXPECT_NE(none.error().find("selector 2"), std::string::npos) << none.error();
  EXPECT_NE(none.error().find("video1"), std::string::npos) << none.error();
}

TEST(IioSensor, EnablesTheScanReadsRecordsAndStopsWhenTheDeviceCloses) {
  test::TempDir dir("adugs_live");
  test::FakeD435iConfig config;
  config.gyro_bits = 32;
  test::FakeD435i fake(dir.path(), config);
  const data::UsbCamera cam = data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "8086:0b3a").at(0);
  const fs::path gyro_dir = fake.iioDir("gyro_3d");
  {
    data::IioSensor gyro(cam.iio[1], "anglvel", 400, 512);
    EXPECT_EQ(test::readFirstLine(gyro_dir / "scan_elements/in_anglvel_x_en"), "1");
    EXPECT_EQ(test::readFirstLine(gyro_dir / "scan_elements/in_timestamp_en"), "1");
    EXPECT_EQ(test::readFirstLine(gyro_dir / "in_anglvel_sampling_frequency"), "400");
    EXPECT_EQ(gyro.rateHz(), 400.0);
    EXPECT_EQ(test::readFirstLine(gyro_dir / "buffer/length"), "512");
    EXPECT_EQ(test::readFirstLine(gyro_dir / "buffer/enable"), "1");
    EXPECT_EQ(test::readFirstLine(gyro_dir / "trigger/current_trigger"), "gyro_3d-dev2");
    EXPECT_EQ(gyro.hostStampClock(), "realtime");
    EXPECT_EQ(gyro.axisRealBits(), 32);
    EXPECT_EQ(gyro.recordBytes(), 24u);

    const int w = ::open(cam.iio[1].dev_path.c_str(), O_WRONLY | O_NONBLOCK);
    ASSERT_GE(w, 0);
    std::vector<uint8_t> bytes = test::hidImuRecord(-70000, 5, 6, 4'000'000'000'000ll, 4);
    const std::vector<uint8_t> second = test::hidImuRecord(1, 2, 3, 4'000'002'500'000ll, 4);
    bytes.insert(bytes.end(), second.begin(), second.begin() + 10);  // a record cut in two writes
    ASSERT_EQ(::write(w, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    std::vector<data::IioSample> got;
    ASSERT_TRUE(readable(gyro.fd(), 100));
    ASSERT_TRUE(gyro.read(&got));
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].counts, Eigen::Vector3d(-70000, 5, 6));
    EXPECT_EQ(got[0].timestamp_ns, 4'000'000'000'000ll);
    ASSERT_EQ(::write(w, second.data() + 10, second.size() - 10), static_cast<ssize_t>(second.size() - 10));
    ASSERT_TRUE(readable(gyro.fd(), 100));
    ASSERT_TRUE(gyro.read(&got));
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[1].counts, Eigen::Vector3d(1, 2, 3));
    ::close(w);  // the device goes away
    ASSERT_TRUE(readable(gyro.fd(), 100));
    EXPECT_FALSE(gyro.read(&got));
    EXPECT_TRUE(gyro.gone());
    EXPECT_NE(gyro.message().find("iio:device2"), std::string::npos) << gyro.message();
    EXPECT_NE(gyro.message().find("closed"), std::string::npos) << gyro.message();
  }
  EXPECT_EQ(test::readFirstLine(gyro_dir / "buffer/enable"), "0");  // streaming off again
}

TEST(IioSensor, BadScanElementsNameTheirFile) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  const data::UsbCamera cam = data::findUsbCameras(fake.sysRoot(), fake.devRoot(), "8086:0b3a").at(0);
  const fs::path accel_dir = fake.iioDir("accel_3d");
  test::writeText(accel_dir / "scan_elements/in_accel_y_type", "le:s16\n");
  try {
    data::IioSensor accel(cam.iio[0], "accel", 250, 512);
    FAIL() << "accepted a broken scan type";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("in_accel_y_type"), std::string::npos) << e.what();
  }
  test::writeText(accel_dir / "scan_elements/in_accel_y_type", "le:s16/32>>0\n");
  fs::remove(accel_dir / "scan_elements/in_timestamp_en");
  try {
    data::IioSensor accel(cam.iio[0], "accel", 250, 512);
    FAIL() << "accepted a device without timestamps";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("timestamp"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adugs::data

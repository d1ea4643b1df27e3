// `adugs d435i info` on the simulated camera: what it lists, and the streaming check.
#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <thread>

#include "data/input_error.h"
#include "data/sources/d435i_probe.h"
#include "tests/data/live/fake_d435i.h"
#include "tests/test_support.h"

namespace adugs::data {
namespace {

TEST(D435iProbe, ListsNodesFormatsControlsIioDevicesAndScales) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  std::ostringstream out;
  data::printD435iInfo(out, fake.options(), fake.v4l2());
  const std::string s = out.str();
  for (const char* needle : {"USB 8086:0b3a \"Intel(R) RealSense(TM) Depth Camera 435i\" serial 843112071234 at 2-1 (5000 Mb/s)",
                             "/video0  video capture, uvcvideo", "GREY  8-bit Greyscale: 640x480 (6/15/30/60/90 Hz)",
                             "Y8I ", "/video1  metadata", "formats: D4XX UVCH", "YUYV",
                             "emitter 1 (laser), auto exposure on, exposure 10000 us, gain 16",
                             "/iio:device1  accel_3d", "accel_x      index 0, le:s16/32>>0", "timestamp    index 3, le:s64/64>>0",
                             "in_accel_sampling_frequency", "hysteresis 0; timestamp clock realtime",
                             "gyro data 16-bit: 0.100000 deg/s per LSB (firmware before 5.16)",
                             "the options would use: infrared ", "/video0 + metadata "})
    EXPECT_NE(s.find(needle), std::string::npos) << needle << "\n" << s;
  EXPECT_EQ(s.find("iio:device0"), std::string::npos) << "listed the laptop's sensor hub\n" << s;
  EXPECT_EQ(s.find("video4"), std::string::npos) << "listed the webcam\n" << s;

  data::D435iOptions none = fake.options();
  none.usb_id = "8086:0b07";
  try {
    data::printD435iInfo(out, none, fake.v4l2());
    FAIL() << "found a D435";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("8086:0b3a"), std::string::npos) << e.what();  // what is there
    EXPECT_NE(std::string(e.what()).find("04f2:b6dd"), std::string::npos) << e.what();
  }
}

TEST(D435iProbe, StreamCheckReportsRatesAndTheClock) {
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  std::ostringstream out;
  // The device starts once the check has opened everything: its last step turns the infrared node's
  // streaming on (after the IIO FIFOs were opened), an event of the fake, not a guessed delay.
  bool started = false;
  std::thread starter([&] {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);  // hang guard only
    while (!fake.v4l2().state(fake.devRoot() + "/video0").streaming && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    started = fake.v4l2().state(fake.devRoot() + "/video0").streaming;
    if (started) fake.start();
  });
  data::printD435iStreamCheck(out, fake.options(), 1.5, fake.v4l2());
  starter.join();
  fake.stop();
  ASSERT_TRUE(started) << "the stream check never turned the infrared node's streaming on (30 s)\n" << out.str();
  const std::string s = out.str();
  for (const char* needle : {"streaming 1.5 s", "frames ", "IMU ", "lost: 0 frames by the driver",
                             "frames on the camera clock (metadata), IMU on the camera clock"})
    EXPECT_NE(s.find(needle), std::string::npos) << needle << "\n" << s;
  // Rates on the host clock (the device's is 50 ppm fast: 30.0015 Hz, printed to 4 digits).
  EXPECT_NE(s.find("(30 Hz, interval"), std::string::npos) << s;
  EXPECT_NE(s.find("(400 Hz, interval"), std::string::npos) << s;
}

TEST(D435iProbe, TheCommandLineReportsUnopenableNodesAndStillListsTheImu) {
  // The real system calls on the fake tree: its /dev has FIFOs for the IIO devices but no video
  // nodes, so opening them fails with a message instead of stopping the listing.
  test::TempDir dir("adugs_live");
  test::FakeD435i fake(dir.path());
  std::string log;
  ASSERT_EQ(test::runAdugs("d435i info --sys-root " + fake.sysRoot() + " --dev-root " + fake.devRoot(), &log), 0) << log;
  EXPECT_NE(log.find("/video0: cannot open: No such file or directory"), std::string::npos) << log;
  EXPECT_NE(log.find("gyro_3d"), std::string::npos) << log;
  EXPECT_NE(log.find("access ok"), std::string::npos) << log;  // the FIFO is readable
  EXPECT_EQ(test::runAdugs("d435i info --usb-id 8086:0b07 --sys-root " + fake.sysRoot() + " --dev-root " + fake.devRoot(), &log), 2)
      << log;
  EXPECT_NE(log.find("no USB camera 8086:0b07"), std::string::npos) << log;
}

}  // namespace
}  // namespace adugs::data

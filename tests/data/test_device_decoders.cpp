// The decoders of live device bytes (data/device/): V4L2 pixel formats, UVC / D4xx metadata, IIO
// scan elements and records, RealSense IMU units and axes, on buffers built here by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "data/device/iio_scan.h"
#include "data/device/pixel_formats.h"
#include "data/device/realsense_imu.h"
#include "data/device/uvc_metadata.h"
#include "data/input_error.h"
#include "tests/device_bytes.h"

namespace adugs::data {
namespace {

TEST(PixelFormats, Y8iSplitsLeftLowByteAndRightHighByteWithPaddedRows) {
  const int w = 3, h = 2, stride = 8;  // 6 bytes of pixels + 2 of padding per row
  std::vector<uint8_t> buf(stride * h, 0xee);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      buf[y * stride + 2 * x] = static_cast<uint8_t>(10 * y + x);         // left
      buf[y * stride + 2 * x + 1] = static_cast<uint8_t>(100 + 10 * y + x);  // right
    }
  cv::Mat left, right;
  ASSERT_TRUE(splitY8i(buf.data(), buf.size(), w, h, stride, &left, &right));
  ASSERT_EQ(left.type(), CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      EXPECT_EQ(left.at<uint8_t>(y, x), 10 * y + x);
      EXPECT_EQ(right.at<uint8_t>(y, x), 100 + 10 * y + x);
    }
  cv::Mat grey;
  ASSERT_TRUE(decodeGrey(PixelFormat::kY8i, buf.data(), buf.size(), w, h, stride, &grey));
  EXPECT_EQ(cv::norm(grey, left, cv::NORM_INF), 0);
}

TEST(PixelFormats, GreyAndYuyvLuma) {
  // GREY 4x2 with a 6-byte stride; the last row needs only its 4 pixels.
  std::vector<uint8_t> grey_buf = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8};
  cv::Mat g;
  ASSERT_TRUE(decodeGrey(PixelFormat::kGrey, grey_buf.data(), grey_buf.size(), 4, 2, 6, &g));
  EXPECT_EQ(g.at<uint8_t>(0, 3), 4);
  EXPECT_EQ(g.at<uint8_t>(1, 0), 5);
  EXPECT_EQ(g.at<uint8_t>(1, 3), 8);
  // YUYV 2x1: Y0 U Y1 V.
  std::vector<uint8_t> yuyv = {50, 128, 60, 129};
  ASSERT_TRUE(decodeGrey(PixelFormat::kYuyv, yuyv.data(), yuyv.size(), 2, 1, 0, &g));
  EXPECT_EQ(g.at<uint8_t>(0, 0), 50);
  EXPECT_EQ(g.at<uint8_t>(0, 1), 60);
}

TEST(PixelFormats, YuyvToBgr) {
  // Two pixels of neutral chroma (U = V = 128): grey, BT.601 limited range (UVC's YUYV), 1.164 (Y - 16);
  // then a red-shifted pair.
  const std::vector<uint8_t> grey = {100, 128, 200, 128};
  cv::Mat bgr;
  ASSERT_TRUE(decodeYuyvToBgr(grey.data(), grey.size(), 2, 1, 0, &bgr));
  ASSERT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(98, 98, 98));     // 1.164 * 84 = 97.8
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(214, 214, 214));  // 1.164 * 184 = 214.2
  const std::vector<uint8_t> red = {100, 128, 100, 200};  // V > 128: more red, less green
  ASSERT_TRUE(decodeYuyvToBgr(red.data(), red.size(), 2, 1, 0, &bgr));
  const cv::Vec3b p = bgr.at<cv::Vec3b>(0, 0);
  EXPECT_GT(p[2], 150);  // R
  EXPECT_LT(p[1], 100);  // G
  EXPECT_FALSE(decodeYuyvToBgr(red.data(), 3, 2, 1, 0, &bgr));
}

TEST(PixelFormats, TruncatedBuffersAreRefused) {
  std::vector<uint8_t> buf(2 * 4 * 3 - 1);  // a 4x3 Y8I image needs 24 bytes
  cv::Mat l, r, g;
  EXPECT_FALSE(splitY8i(buf.data(), buf.size(), 4, 3, 0, &l, &r));
  EXPECT_FALSE(decodeGrey(PixelFormat::kY8i, buf.data(), buf.size(), 4, 3, 0, &g));
  EXPECT_FALSE(decodeGrey(PixelFormat::kGrey, buf.data(), buf.size(), 4, 3, 2, &g));  // stride < width
  EXPECT_TRUE(l.empty());
  EXPECT_TRUE(g.empty());
}

TEST(PixelFormats, FourccRoundTrip) {
  EXPECT_EQ(fourcc(PixelFormat::kGrey), 0x59455247u);  // 'G' 'R' 'E' 'Y' little-endian
  EXPECT_EQ(toString(PixelFormat::kY8i), "Y8I");
  PixelFormat f;
  ASSERT_TRUE(pixelFormatFromFourcc(fourcc(PixelFormat::kYuyv), &f));
  EXPECT_EQ(f, PixelFormat::kYuyv);
  EXPECT_FALSE(pixelFormatFromFourcc(0x2036315a, &f));  // "Z16 "
  EXPECT_EQ(fourccText(0x2036315a), "Z16");
}

TEST(UvcMetadata, D4xxBlockGivesHostTimePtsAndCaptureTiming) {
  test::D4xxMetadataFields f;
  f.host_ns = 123456789012345ull;
  f.sof = 777;
  f.pts_us = 4294967000u;
  f.frame_counter = 42;
  f.sensor_timestamp_us = 4294960000u;
  f.exposure_us = 8500;
  f.readout_us = 10000;
  f.frame_interval_us = 33333;
  f.pipe_latency_us = 500;
  const std::vector<uint8_t> b = test::d4xxMetadataBlock(f);
  UvcFrameMetadata m;
  ASSERT_TRUE(parseUvcMetadata(b.data(), b.size(), &m));
  EXPECT_EQ(m.host_ns, 123456789012345ll);
  EXPECT_EQ(m.sof, 777);
  EXPECT_TRUE(m.has_pts);
  EXPECT_EQ(m.pts_us, 4294967000u);
  ASSERT_TRUE(m.has_capture_timing);
  EXPECT_TRUE(m.has_frame_counter && m.has_sensor_timestamp && m.has_exposure);
  EXPECT_EQ(m.frame_counter, 42u);
  EXPECT_EQ(m.sensor_timestamp_us, 4294960000u);
  EXPECT_EQ(m.exposure_us, 8500u);
  EXPECT_EQ(m.readout_us, 10000u);
  EXPECT_EQ(m.frame_interval_us, 33333u);
  EXPECT_EQ(m.pipe_latency_us, 500u);
}

TEST(UvcMetadata, StandardHeaderOnlyAndInvalidFlags) {
  test::D4xxMetadataFields f;
  f.capture_timing = false;  // what the plain "UVCH" format gives: 12-byte payload header
  f.pts_us = 1000;
  std::vector<uint8_t> b = test::d4xxMetadataBlock(f);
  UvcFrameMetadata m;
  ASSERT_TRUE(parseUvcMetadata(b.data(), b.size(), &m));
  EXPECT_TRUE(m.has_pts);
  EXPECT_EQ(m.pts_us, 1000u);
  EXPECT_FALSE(m.has_capture_timing);

  f.capture_timing = true;
  f.valid_flags = 0x1;  // only the frame counter is valid
  b = test::d4xxMetadataBlock(f);
  ASSERT_TRUE(parseUvcMetadata(b.data(), b.size(), &m));
  EXPECT_TRUE(m.has_frame_counter);
  EXPECT_FALSE(m.has_sensor_timestamp);
  EXPECT_EQ(m.readout_us, 0u);
}

TEST(UvcMetadata, CaptureTimingFromALaterBlockAndTruncatedBuffers) {
  test::D4xxMetadataFields first;
  first.capture_timing = false;
  first.host_ns = 5000;
  test::D4xxMetadataFields second;
  second.host_ns = 6000;
  second.sensor_timestamp_us = 99;
  std::vector<uint8_t> b = test::d4xxMetadataBlock(first);
  const std::vector<uint8_t> b2 = test::d4xxMetadataBlock(second);
  b.insert(b.end(), b2.begin(), b2.end());
  UvcFrameMetadata m;
  ASSERT_TRUE(parseUvcMetadata(b.data(), b.size(), &m));
  EXPECT_EQ(m.host_ns, 5000);  // the first block's arrival time
  ASSERT_TRUE(m.has_capture_timing);
  EXPECT_EQ(m.sensor_timestamp_us, 99u);

  // A buffer cut inside the capture-timing record: header still usable, record not.
  const std::vector<uint8_t> full = test::d4xxMetadataBlock(second);
  std::vector<uint8_t> cut(full.begin(), full.begin() + 30);
  cut[10] = 12;  // the cut block claims only the standard header
  ASSERT_TRUE(parseUvcMetadata(cut.data(), cut.size(), &m));
  EXPECT_FALSE(m.has_capture_timing);
  EXPECT_FALSE(parseUvcMetadata(full.data(), 11, &m));
  std::vector<uint8_t> lying = full;
  lying[10] = 200;  // length beyond the buffer
  EXPECT_FALSE(parseUvcMetadata(lying.data(), lying.size(), &m));
}

TEST(IioScan, ParsesScanTypes) {
  IioScanType t = parseIioScanType("le:s16/32>>0\n", "in_anglvel_x_type");
  EXPECT_FALSE(t.big_endian);
  EXPECT_TRUE(t.is_signed);
  EXPECT_EQ(t.real_bits, 16);
  EXPECT_EQ(t.storage_bits, 32);
  EXPECT_EQ(t.shift, 0);
  EXPECT_EQ(t.repeat, 1);
  t = parseIioScanType("be:u12/16>>4", "f");
  EXPECT_TRUE(t.big_endian);
  EXPECT_FALSE(t.is_signed);
  EXPECT_EQ(t.real_bits, 12);
  EXPECT_EQ(t.shift, 4);
  t = parseIioScanType("le:s16/16X3>>0", "f");
  EXPECT_EQ(t.repeat, 3);
  for (const char* bad : {"", "le:s16/32", "xe:s16/32>>0", "le:q16/32>>0", "le:s33/32>>0", "le:s16/24>>0",
                          "le:s16/16>>4", "le:s16/32>>0 junk", "lle:s16/32>>0",
                          // negative numbers, which %u reads as huge ones (shift -1 wrapped the check)
                          "le:s2/8>>-1", "le:s-1/8>>0", "le:s8/8X-1>>0", "le:s+8/8>>0"}) {
    try {
      parseIioScanType(bad, "/sys/bus/iio/devices/iio:device1/scan_elements/in_accel_x_type");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("in_accel_x_type"), std::string::npos) << e.what();
    }
  }
}

std::vector<IioChannel> hidChannels(const std::string& type_xyz) {
  std::vector<IioChannel> c;
  // Given out of index order, as a directory listing would.
  c.push_back({"timestamp", 3, parseIioScanType("le:s64/64>>0", "t"), 0});
  c.push_back({"accel_z", 2, parseIioScanType(type_xyz, "z"), 0});
  c.push_back({"accel_x", 0, parseIioScanType(type_xyz, "x"), 0});
  c.push_back({"accel_y", 1, parseIioScanType(type_xyz, "y"), 0});
  return c;
}

TEST(IioScan, RecordLayoutAlignsEachElementAndPadsTheRecord) {
  std::vector<IioChannel> c = hidChannels("le:s16/32>>0");
  EXPECT_EQ(layoutIioRecord(&c, "iio:device1"), 24u);  // 3 x 4, 4 padding, 8
  EXPECT_EQ(c[0].name, "accel_x");
  EXPECT_EQ(c[0].offset, 0u);
  EXPECT_EQ(c[1].offset, 4u);
  EXPECT_EQ(c[2].offset, 8u);
  EXPECT_EQ(c[3].name, "timestamp");
  EXPECT_EQ(c[3].offset, 16u);
  c = hidChannels("le:s16/16>>0");
  EXPECT_EQ(layoutIioRecord(&c, "iio:device1"), 16u);  // 3 x 2, 2 padding, 8
  EXPECT_EQ(c[3].offset, 8u);
  std::vector<IioChannel> odd = {{"a", 0, parseIioScanType("le:u8/8>>0", "a"), 0},
                                 {"b", 1, parseIioScanType("le:u16/16>>0", "b"), 0}};
  EXPECT_EQ(layoutIioRecord(&odd, "d"), 4u);  // a at 0, b at 2, size 4
  EXPECT_EQ(odd[1].offset, 2u);
  std::vector<IioChannel> dup = {{"a", 1, parseIioScanType("le:u8/8>>0", "a"), 0},
                                 {"b", 1, parseIioScanType("le:u8/8>>0", "b"), 0}};
  EXPECT_THROW(layoutIioRecord(&dup, "d"), InputError);
}

TEST(IioScan, DecodesSignExtendsMasksAndShifts) {
  std::vector<IioChannel> c = hidChannels("le:s16/32>>0");
  layoutIioRecord(&c, "d");
  // 16 meaningful bits in 32 with junk in the upper half (the kernel copies 4 bytes of a 2-byte field).
  const std::vector<uint8_t> r = test::hidImuRecord(-2, 32767, -32768, 1234567890123ll, 2);
  EXPECT_EQ(decodeIioValue(r.data(), c[0]), -2);
  EXPECT_EQ(decodeIioValue(r.data(), c[1]), 32767);
  EXPECT_EQ(decodeIioValue(r.data(), c[2]), -32768);
  EXPECT_EQ(decodeIioValue(r.data(), c[3]), 1234567890123ll);
  c = hidChannels("le:s32/32>>0");
  layoutIioRecord(&c, "d");
  const std::vector<uint8_t> r32 = test::hidImuRecord(-100000, 2000000, 0, -5, 4);
  EXPECT_EQ(decodeIioValue(r32.data(), c[0]), -100000);
  EXPECT_EQ(decodeIioValue(r32.data(), c[1]), 2000000);
  EXPECT_EQ(decodeIioValue(r32.data(), c[3]), -5);
  // Big-endian 12 bits shifted by 4: bytes 0xAB 0xC0 -> 0xABC; signed 12-bit 0xABC = -1348.
  IioChannel be{"v", 0, parseIioScanType("be:u12/16>>4", "v"), 0};
  const uint8_t bytes[2] = {0xAB, 0xC5};
  EXPECT_EQ(decodeIioValue(bytes, be), 0xABC);
  be.type.is_signed = true;
  EXPECT_EQ(decodeIioValue(bytes, be), 0xABC - 4096);
  IioChannel rep{"r", 0, parseIioScanType("le:s16/16X3>>0", "r"), 0};
  const uint8_t triple[6] = {1, 0, 0xff, 0xff, 3, 0};
  EXPECT_EQ(decodeIioValue(triple, rep, 1), -1);
  EXPECT_EQ(decodeIioValue(triple, rep, 2), 3);
}

TEST(RealsenseImu, UnitsFollowTheFirmwareWidthAndAxesTurnIntoTheCameraFrame) {
  EXPECT_DOUBLE_EQ(realsenseGyroLsbDegPerSec(16), 0.1);
  EXPECT_DOUBLE_EQ(realsenseGyroLsbDegPerSec(32), 0.0001);
  EXPECT_EQ(realsenseGyroLsbDegPerSec(12), 0.0);
  // 16-bit firmware: 900 counts = 90 deg/s about the raw x axis -> -pi/2 rad/s about camera x.
  const Eigen::Vector3d w = realsenseGyroToBody({900, -450, 300}, realsenseGyroLsbDegPerSec(16));
  EXPECT_NEAR(w.x(), -M_PI / 2, 1e-12);
  EXPECT_NEAR(w.y(), -M_PI / 4, 1e-12);
  EXPECT_NEAR(w.z(), -M_PI / 6, 1e-12);
  // 32-bit firmware: 900000 counts = 90 deg/s.
  EXPECT_NEAR(realsenseGyroToBody({0, 900000, 0}, realsenseGyroLsbDegPerSec(32)).y(), M_PI / 2, 1e-12);
  // Lying on its back, the raw z axis reads -1 g (1000 counts down): +g on the camera's z.
  const Eigen::Vector3d a = realsenseAccelToBody({0, 0, -1000});
  EXPECT_NEAR(a.z(), 9.80665, 1e-12);
  EXPECT_NEAR(a.x(), 0.0, 1e-12);
  EXPECT_NEAR(realsenseAccelToBody({-500, 250, 0}).x(), 0.5 * 9.80665, 1e-12);
  EXPECT_NEAR(realsenseAccelToBody({-500, 250, 0}).y(), 0.25 * 9.80665, 1e-12);
}

}  // namespace
}  // namespace adugs::data

// ROS image messages to the front-end's 8-bit grey image: every supported encoding on hand-made
// pixels, padded rows, big-endian 16 bit, compressed jpeg/png, and the errors.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"
#include "data/sources/ros_image.h"

namespace adugs::data {
namespace {

sensor_msgs::Image message(const std::string& encoding, int w, int h, int step, std::vector<uint8_t> data) {
  sensor_msgs::Image m;
  m.encoding = encoding;
  m.width = w;
  m.height = h;
  m.step = step;
  m.data = std::move(data);
  return m;
}

TEST(RosImage, ColourEncodingsGiveTheSameLumaInTheirChannelOrder) {
  // One pure red and one pure blue pixel. Luma 0.299 R + 0.587 G + 0.114 B: red 76, blue 29.
  const auto rgb = message("rgb8", 2, 1, 6, {255, 0, 0, 0, 0, 255});
  const auto bgr = message("bgr8", 2, 1, 6, {0, 0, 255, 255, 0, 0});
  const auto rgba = message("rgba8", 2, 1, 8, {255, 0, 0, 7, 0, 0, 255, 7});
  const auto bgra = message("bgra8", 2, 1, 8, {0, 0, 255, 7, 255, 0, 0, 7});
  for (const auto* m : {&rgb, &bgr, &rgba, &bgra}) {
    const cv::Mat g = decodeRosImage(*m, "x.bag", "/cam");
    ASSERT_EQ(g.type(), CV_8UC1) << m->encoding;
    EXPECT_EQ(g.at<uint8_t>(0, 0), 76) << m->encoding;
    EXPECT_EQ(g.at<uint8_t>(0, 1), 29) << m->encoding;
  }
}

TEST(RosImage, MonoEncodingsAndPaddedRows) {
  // 2x2 mono8 with 2 padding bytes per row.
  const cv::Mat g = decodeRosImage(message("mono8", 2, 2, 4, {1, 2, 99, 99, 3, 4, 99, 99}), "x.bag", "/cam");
  EXPECT_EQ(g.at<uint8_t>(0, 1), 2);
  EXPECT_EQ(g.at<uint8_t>(1, 0), 3);
  // mono16 little-endian 0x1234 -> upper byte 0x12 (rounded: 0x1234 / 256 = 18.2 -> 18).
  const cv::Mat m16 = decodeRosImage(message("mono16", 1, 1, 2, {0x34, 0x12}), "x.bag", "/cam");
  EXPECT_EQ(m16.at<uint8_t>(0, 0), 0x12);
  auto big = message("16UC1", 1, 1, 2, {0xAB, 0x80});
  big.is_bigendian = 1;  // 0xAB80 -> 171.5 -> rounds to 172
  EXPECT_EQ(decodeRosImage(big, "x.bag", "/cam").at<uint8_t>(0, 0), 172);
}

TEST(RosImage, CompressedPngAndJpegDecode) {
  cv::Mat picture(16, 24, CV_8UC3, cv::Scalar(0, 0, 255));  // red in BGR
  for (const char* ext : {".png", ".jpg"}) {
    sensor_msgs::CompressedImage m;
    m.format = ext + 1;
    cv::imencode(ext, picture, m.data);
    const cv::Mat g = decodeRosImage(m, "x.bag", "/cam/compressed");
    ASSERT_EQ(g.size(), picture.size());
    EXPECT_NEAR(g.at<uint8_t>(8, 12), 76, 2) << ext;
  }
}

TEST(RosImage, ErrorsNameTheBagTopicAndEncoding) {
  try {
    decodeRosImage(message("yuv422", 2, 1, 4, {0, 0, 0, 0}), "seq.bag", "/d400/color/image_raw");
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("seq.bag"), std::string::npos) << w;
    EXPECT_NE(w.find("/d400/color/image_raw"), std::string::npos) << w;
    EXPECT_NE(w.find("'yuv422'"), std::string::npos) << w;
  }
  EXPECT_THROW(decodeRosImage(message("mono8", 4, 4, 4, {1, 2, 3}), "seq.bag", "/cam"), InputError);
  sensor_msgs::CompressedImage junk;
  junk.format = "jpeg";
  junk.data = {1, 2, 3, 4};
  EXPECT_THROW(decodeRosImage(junk, "seq.bag", "/cam"), InputError);
}

}  // namespace
}  // namespace adugs::data

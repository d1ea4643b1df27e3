#include "data/sources/ros_image.h"

#include <opencv2/imgproc.hpp>

#include "data/formats/image_file.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {

struct Layout {
  int cv_type;
  int channels;
  int color_code;  // cv::cvtColor code to grey, -1 = already grey
};

bool layoutOf(const std::string& encoding, Layout* l) {
  if (encoding == "mono8" || encoding == "8UC1") *l = {CV_8UC1, 1, -1};
  else if (encoding == "mono16" || encoding == "16UC1") *l = {CV_16UC1, 1, -1};
  else if (encoding == "bgr8" || encoding == "8UC3") *l = {CV_8UC3, 3, cv::COLOR_BGR2GRAY};
  else if (encoding == "rgb8") *l = {CV_8UC3, 3, cv::COLOR_RGB2GRAY};
  else if (encoding == "bgra8" || encoding == "8UC4") *l = {CV_8UC4, 4, cv::COLOR_BGRA2GRAY};
  else if (encoding == "rgba8") *l = {CV_8UC4, 4, cv::COLOR_RGBA2GRAY};
  else return false;
  return true;
}

cv::Mat toEightBitGrey(const cv::Mat& image, int color_code) {
  cv::Mat grey;
  if (image.depth() == CV_16U) {
    image.convertTo(grey, CV_8U, 1.0 / 256.0);
  } else if (color_code >= 0) {
    cv::cvtColor(image, grey, color_code);
  } else {
    grey = image.clone();  // the message buffer is reused by the next read
  }
  return grey;
}

}  // namespace

const char* supportedRosImageEncodings() {
  return "mono8, 8UC1, mono16, 16UC1, bgr8, 8UC3, rgb8, bgra8, 8UC4, rgba8; CompressedImage jpeg/png";
}

cv::Mat decodeRosImage(const sensor_msgs::Image& msg, const std::string& file, const std::string& topic) {
  const std::string field = "topic " + topic;
  Layout l;
  if (!layoutOf(msg.encoding, &l))
    throw InputError(file, 0, field,
                     "unsupported image encoding '" + msg.encoding + "' (supported: " +
                         supportedRosImageEncodings() + ")");
  const size_t pixel_bytes = static_cast<size_t>(CV_ELEM_SIZE(l.cv_type));
  if (msg.width == 0 || msg.height == 0 || msg.step < msg.width * pixel_bytes ||
      msg.data.size() < static_cast<size_t>(msg.step) * msg.height)
    throw InputError(file, 0, field,
                     "image message of " + std::to_string(msg.width) + "x" + std::to_string(msg.height) +
                         " " + msg.encoding + " has step " + std::to_string(msg.step) + " and " +
                         std::to_string(msg.data.size()) + " data bytes: inconsistent");
  const cv::Mat view(static_cast<int>(msg.height), static_cast<int>(msg.width), l.cv_type,
                     const_cast<uint8_t*>(msg.data.data()), msg.step);
  if (l.cv_type == CV_16UC1 && msg.is_bigendian) {
    cv::Mat swapped = view.clone();
    for (int r = 0; r < swapped.rows; ++r) {
      auto* row = swapped.ptr<uint16_t>(r);
      for (int c = 0; c < swapped.cols; ++c) row[c] = static_cast<uint16_t>((row[c] >> 8) | (row[c] << 8));
    }
    return toEightBitGrey(swapped, l.color_code);
  }
  return toEightBitGrey(view, l.color_code);
}

cv::Mat decodeRosImage(const sensor_msgs::CompressedImage& msg, const std::string& file,
                       const std::string& topic) {
  std::string why;
  const cv::Mat image = decodeImage(msg.data, ImageRead::kGrey, &why);
  if (image.empty())
    throw InputError(file, 0, "topic " + topic,
                     "compressed image (format '" + msg.format + "', " + std::to_string(msg.data.size()) +
                         " bytes) cannot be decoded: " + why);
  return image;
}

}  // namespace adugs::data

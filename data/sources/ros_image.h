#pragma once
// Decodes ROS image messages into the 8-bit grey image the front-end tracks on.
//   sensor_msgs/Image: mono8, 8UC1 (as is), mono16, 16UC1 (upper 8 bits, as OpenCV's imread does
//   for 16-bit PNGs), bgr8, rgb8, bgra8, rgba8 (cv::cvtColor's ITU-R 601 luma, the weights
//   imread uses for colour files). Rows may be padded (step > width * pixel size); big-endian
//   16-bit data is byte-swapped.
//   sensor_msgs/CompressedImage: PNG or JPEG (others through OpenCV: data/formats/image_file.h),
//   converted to grey.
// Anything else is an InputError naming the bag, the topic and the encoding.
#include <string>

#include <opencv2/core.hpp>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

namespace adugs::data {

// The encodings decodeRosImage accepts, for error messages and `adugs bag info`.
const char* supportedRosImageEncodings();

// `where` names the message in errors: "FILE.bag", "topic /cam0/image_raw".
cv::Mat decodeRosImage(const sensor_msgs::Image& msg, const std::string& file, const std::string& topic);
cv::Mat decodeRosImage(const sensor_msgs::CompressedImage& msg, const std::string& file,
                       const std::string& topic);

}  // namespace adugs::data

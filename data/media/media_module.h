#pragma once
// OpenCV's video and image-codec libraries live in a module, libadugs_media.so, that adugs opens
// only when it needs them: a video file, a V4L2 webcam, an overlay video, or an image file in a
// format other than PNG and JPEG (which data/formats/image_file.h reads and writes itself with
// libpng and libjpeg). Debian builds imgcodecs with GDAL (poppler, proj, xerces behind it) and
// videoio with ffmpeg and GStreamer: loaded, they cost every process ~50 MB, most of what a plain
// `adugs run` would otherwise hold. This header is the contract between the binary
// (data/media/media_loader) and the module (data/media/opencv_media.cpp): one C entry point that
// hands over a table of functions working on C++ objects (one compiler and standard library for
// both). Property ids are OpenCV's cv::CAP_PROP_* (constants of opencv2/videoio.hpp; the library
// itself is not linked into adugs).
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace adugs::data {

// The part of cv::VideoCapture adugs uses.
class VideoInput {
 public:
  virtual ~VideoInput() = default;
  virtual bool read(cv::Mat& frame) = 0;
  virtual double get(int property) const = 0;
  virtual bool set(int property, double value) = 0;
};

// The part of cv::VideoWriter adugs uses.
class VideoOutput {
 public:
  virtual ~VideoOutput() = default;
  virtual void write(const cv::Mat& frame) = 0;
};

// How an image file is read, as cv::imread's IMREAD_GRAYSCALE and IMREAD_UNCHANGED.
enum class ImageRead { kGrey, kUnchanged };

// Each function returns nullptr / an empty image / false when OpenCV cannot do it (the caller
// names the file); the caller owns the returned objects.
struct MediaFunctions {
  VideoInput* (*open_video_file)(const std::string& path);
  VideoInput* (*open_v4l2_camera)(const std::string& device);  // cv::CAP_V4L2
  VideoOutput* (*open_video_writer)(const std::string& path, int fourcc, double fps, cv::Size size);
  cv::Mat (*read_image)(const std::string& path, ImageRead mode);
  cv::Mat (*decode_image)(const std::vector<uint8_t>& bytes, ImageRead mode);
  bool (*encode_image)(const std::string& extension, const cv::Mat& image, std::vector<uint8_t>& bytes);
};

inline constexpr const char* kMediaModuleFile = "libadugs_media.so";
inline constexpr const char* kMediaFunctionsSymbol = "adugs_media_functions";
using GetMediaFunctions = const MediaFunctions* (*)();

// A FourCC code as OpenCV writes it (cv::VideoWriter::fourcc, which lives in videoio).
constexpr int fourccCode(char a, char b, char c, char d) {
  return (a & 255) | ((b & 255) << 8) | ((c & 255) << 16) | ((d & 255) << 24);
}

}  // namespace adugs::data

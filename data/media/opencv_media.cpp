// The body of libadugs_media.so (data/media/media_module.h): OpenCV's videoio and imgcodecs.
#include <memory>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "data/media/media_module.h"

namespace adugs::data {
namespace {

class OpenCvVideoInput : public VideoInput {
 public:
  bool open(const std::string& path, int api) { return capture_.open(path, api) && capture_.isOpened(); }
  bool read(cv::Mat& frame) override { return capture_.read(frame); }
  double get(int property) const override { return capture_.get(property); }
  bool set(int property, double value) override { return capture_.set(property, value); }

 private:
  cv::VideoCapture capture_;
};

class OpenCvVideoOutput : public VideoOutput {
 public:
  bool open(const std::string& path, int fourcc, double fps, cv::Size size) {
    return writer_.open(path, fourcc, fps, size) && writer_.isOpened();
  }
  void write(const cv::Mat& frame) override { writer_.write(frame); }

 private:
  cv::VideoWriter writer_;
};

int imreadFlags(ImageRead mode) { return mode == ImageRead::kGrey ? cv::IMREAD_GRAYSCALE : cv::IMREAD_UNCHANGED; }

VideoInput* openInput(const std::string& path, int api) {
  auto input = std::make_unique<OpenCvVideoInput>();
  try {
    if (!input->open(path, api)) return nullptr;
  } catch (const cv::Exception&) {
    return nullptr;
  }
  return input.release();
}

const MediaFunctions kFunctions = {
    [](const std::string& path) { return openInput(path, cv::CAP_ANY); },
    [](const std::string& device) { return openInput(device, cv::CAP_V4L2); },
    [](const std::string& path, int fourcc, double fps, cv::Size size) -> VideoOutput* {
      auto output = std::make_unique<OpenCvVideoOutput>();
      try {
        if (!output->open(path, fourcc, fps, size)) return nullptr;
      } catch (const cv::Exception&) {
        return nullptr;
      }
      return output.release();
    },
    [](const std::string& path, ImageRead mode) {
      try {
        return cv::imread(path, imreadFlags(mode));
      } catch (const cv::Exception&) {
        return cv::Mat();
      }
    },
    [](const std::vector<uint8_t>& bytes, ImageRead mode) {
      try {
        return cv::imdecode(bytes, imreadFlags(mode));
      } catch (const cv::Exception&) {
        return cv::Mat();
      }
    },
    [](const std::string& extension, const cv::Mat& image, std::vector<uint8_t>& bytes) {
      try {
        return cv::imencode(extension, image, bytes);
      } catch (const cv::Exception&) {
        return false;
      }
    },
};

}  // namespace
}  // namespace adugs::data

extern "C" const adugs::data::MediaFunctions* adugs_media_functions() { return &adugs::data::kFunctions; }

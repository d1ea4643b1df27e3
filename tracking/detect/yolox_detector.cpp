#include "tracking/detect/yolox_detector.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "data/input_error.h"
#include "tracking/detect/letterbox.h"

namespace adugs::tracking {
namespace {

// Anchors of the stride-8/16/32 grids in YOLOX's order: stride by stride, row-major.
int anchorCount(int input_size) {
  int n = 0;
  for (int stride : {8, 16, 32}) n += (input_size / stride) * (input_size / stride);
  return n;
}

}  // namespace

std::vector<Detection> decodeYoloxOutput(const cv::Mat& output, int input_size, double ratio,
                                         const YoloxOptions& options) {
  std::vector<Detection> out;
  const int classes = output.cols - 5;
  int row = 0;
  for (int stride : {8, 16, 32}) {
    const int cells = input_size / stride;
    for (int gy = 0; gy < cells; ++gy) {
      for (int gx = 0; gx < cells; ++gx, ++row) {
        const float* a = output.ptr<float>(row);
        const float* cls = a + 5;
        const int best = static_cast<int>(std::max_element(cls, cls + classes) - cls);
        const double score = a[4] * cls[best];
        if (score < options.score_threshold || !options.keep_classes.count(best)) continue;
        Detection d;
        d.box.cx = (a[0] + gx) * stride / ratio;
        d.box.cy = (a[1] + gy) * stride / ratio;
        d.box.w = std::exp(a[2]) * stride / ratio;
        d.box.h = std::exp(a[3]) * stride / ratio;
        d.class_id = best;
        d.score = score;
        out.push_back(d);
      }
    }
  }
  return out;
}

YoloxDetector::YoloxDetector(const std::string& onnx_path, const YoloxOptions& options)
    : path_(onnx_path), options_(options) {
  if (!std::filesystem::is_regular_file(onnx_path))
    throw data::InputError(onnx_path, 0, "model", "YOLOX ONNX model file not found");
  try {
    net_ = cv::dnn::readNetFromONNX(onnx_path);
  } catch (const cv::Exception& e) {
    throw data::InputError(onnx_path, 0, "model",
                           std::string("OpenCV dnn cannot load it: ") + e.what());
  }
  if (net_.empty())
    throw data::InputError(onnx_path, 0, "model", "OpenCV dnn loaded an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  // Check the output layout once on a blank image.
  const cv::Mat probe(options_.input_size, options_.input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  net_.setInput(cv::dnn::blobFromImage(probe, 1.0, cv::Size(), cv::Scalar(), false, false, CV_32F));
  cv::Mat out;
  try {
    out = net_.forward();
  } catch (const cv::Exception& e) {
    throw data::InputError(onnx_path, 0, "model",
                           std::string("the network does not run: ") + e.what());
  }
  const int expected = anchorCount(options_.input_size);
  if (out.dims != 3 || out.size[1] != expected || out.size[2] < 6)
    throw data::InputError(onnx_path, 0, "output",
                           "not a YOLOX output for input " + std::to_string(options_.input_size) +
                               ": expected 1x" + std::to_string(expected) + "x(5+classes)");
}

std::vector<Detection> YoloxDetector::detect(const cv::Mat& image) {
  const int s = options_.input_size;
  const Letterbox input = letterbox(image, {s, s}, LetterboxPlacement::kTopLeft);
  net_.setInput(
      cv::dnn::blobFromImage(input.image, 1.0, cv::Size(), cv::Scalar(), false, false, CV_32F));
  cv::Mat out = net_.forward();
  const cv::Mat rows(out.size[1], out.size[2], CV_32F, out.ptr<float>());
  return suppressOverlaps(decodeYoloxOutput(rows, s, input.scale, options_), options_.score_threshold,
                          options_.nms_iou);
}

}  // namespace adugs::tracking

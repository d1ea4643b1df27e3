#include "tracking/detect/ultralytics_onnx_detector.h"

#include "data/input_error.h"

namespace adugs::tracking {
namespace {

const char* const kPrepareHint =
    " (OpenCV 4.6 needs ultralytics' ONNX exports prepared first: "
    "/usr/bin/python3 scripts/prepare_onnx_for_opencv.py IN.onnx OUT.onnx; or use the "
    "TorchScript export, format=torchscript)";

}  // namespace

UltralyticsOnnxDetector::UltralyticsOnnxDetector(const std::string& onnx_path, const OnnxSignature& signature,
                                                 const DetectorOptions& options)
    : path_(onnx_path), options_(options) {
  info_ = parseUltralyticsMetadata(signature.metadata, onnx_path);
  const OnnxTensorInfo& input = signature.inputs.front();
  if (info_.input_size.empty() && input.dims.size() == 4 && input.dims[2] > 0 && input.dims[3] > 0)
    info_.input_size = {static_cast<int>(input.dims[3]), static_cast<int>(input.dims[2])};
  if (info_.input_size.empty())
    throw data::InputError(onnx_path, 0, "imgsz",
                           "neither the metadata nor the input shape " + describeShape(input) +
                               " gives the network's input size (export with a fixed imgsz)");
  options_.keep_classes = keptClasses(info_, options_.keep_classes, onnx_path);
  try {
    net_ = cv::dnn::readNetFromONNX(onnx_path);
  } catch (const cv::Exception& e) {
    throw data::InputError(onnx_path, 0, "model", std::string("OpenCV dnn cannot import it: ") + e.what() + kPrepareHint);
  }
  if (net_.empty()) throw data::InputError(onnx_path, 0, "model", "OpenCV dnn loaded an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  // One run on a grey frame checks the layout now rather than on the first frame.
  const cv::Mat grey(info_.input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  const cv::Mat out = forward(cv::dnn::blobFromImage(grey, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false, CV_32F));
  num_classes_ = ultralyticsClassCount(out.size[1], info_, onnx_path);
}

cv::Mat UltralyticsOnnxDetector::forward(const cv::Mat& blob) {
  cv::Mat out;
  try {
    net_.setInput(blob);
    out = net_.forward();
  } catch (const cv::Exception& e) {
    throw data::InputError(path_, 0, "model", std::string("OpenCV dnn cannot run it: ") + e.what() + kPrepareHint);
  }
  if (out.dims != 3 || out.size[0] != 1 || out.size[1] >= out.size[2])
    throw data::InputError(path_, 0, "output", "not an ultralytics detect output 1 x (4 + classes) x anchors");
  return out;
}

std::vector<Detection> UltralyticsOnnxDetector::detect(const cv::Mat& image) {
  const Letterbox input = letterbox(image, info_.input_size, LetterboxPlacement::kCentred);
  const cv::Mat out =
      forward(cv::dnn::blobFromImage(input.image, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false, CV_32F));
  const cv::Mat rows(out.size[1], out.size[2], CV_32F, const_cast<float*>(out.ptr<float>()));
  return suppressOverlaps(decodeUltralyticsOutput(rows, num_classes_, input, options_), options_.score_threshold,
                          options_.nms_iou);
}

}  // namespace adugs::tracking

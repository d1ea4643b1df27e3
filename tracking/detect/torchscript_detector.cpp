#include "tracking/detect/torchscript_detector.h"

#include <yaml-cpp/yaml.h>

#include <opencv2/dnn.hpp>

#include "data/input_error.h"
#include "tracking/torchscript_module.h"

namespace adugs::tracking {
namespace {

constexpr const char* kWhat = "ultralytics YOLO TorchScript export";
constexpr int kDefaultInputSide = 640;  // ultralytics' default imgsz, for archives without config.txt

}  // namespace

struct TorchScriptDetector::Model {
  torch::jit::Module module;
};

TorchScriptDetector::TorchScriptDetector(const std::string& path, const DetectorOptions& options)
    : model_(std::make_unique<Model>()), path_(path), options_(options) {
  std::unordered_map<std::string, std::string> extra = {{"config.txt", ""}};
  model_->module = loadTorchScript(path, kWhat, &extra);
  requireForwardInputs(model_->module, {"images"}, path, kWhat);
  if (!extra["config.txt"].empty()) {
    // config.txt is one JSON object; its values are read like the ONNX metadata entries.
    std::map<std::string, std::string> entries;
    try {
      const YAML::Node root = YAML::Load(extra["config.txt"]);
      for (const auto& kv : root) entries[kv.first.as<std::string>()] = YAML::Dump(kv.second);
    } catch (const YAML::Exception& e) {
      throw data::InputError(path, 0, "config.txt", std::string("the export's metadata is not JSON: ") + e.what());
    }
    info_ = parseUltralyticsMetadata(entries, path + ":config.txt");
  }
  if (info_.input_size.empty()) info_.input_size = {kDefaultInputSide, kDefaultInputSide};
  options_.keep_classes = keptClasses(info_, options_.keep_classes, path);
  // One run on a grey frame checks the output now rather than on the first frame.
  const cv::Mat grey(info_.input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  num_classes_ = ultralyticsClassCount(forward(grey).rows, info_, path);
}

TorchScriptDetector::~TorchScriptDetector() = default;

cv::Mat TorchScriptDetector::forward(const cv::Mat& letterboxed) {
  // NCHW, RGB, 0..1: OpenCV's blob has exactly the tensor's memory layout.
  cv::Mat blob = cv::dnn::blobFromImage(letterboxed, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false, CV_32F);
  const at::Tensor input = torch::from_blob(blob.ptr<float>(), {1, 3, letterboxed.rows, letterboxed.cols});
  const c10::IValue result = runForward(model_->module, {input}, path_);
  // Detect exports return the tensor; segmentation exports a tuple (boxes, mask prototypes).
  at::Tensor out;
  if (result.isTensor()) out = result.toTensor();
  if (result.isTuple() && !result.toTupleRef().elements().empty() && result.toTupleRef().elements()[0].isTensor())
    out = result.toTupleRef().elements()[0].toTensor();
  if (!out.defined() || out.dim() != 3 || out.size(0) != 1 || out.size(1) >= out.size(2))
    throw data::InputError(path_, 0, "output",
                           "not an ultralytics detect output 1 x (4 + classes) x anchors" +
                               (out.defined() ? ": it returns " + shapeOf(out) : std::string(": it returns no tensor")));
  out = out.to(torch::kFloat).contiguous();
  return cv::Mat(static_cast<int>(out.size(1)), static_cast<int>(out.size(2)), CV_32F, out.data_ptr<float>()).clone();
}

std::vector<Detection> TorchScriptDetector::detect(const cv::Mat& image) {
  const Letterbox input = letterbox(image, info_.input_size, LetterboxPlacement::kCentred);
  return suppressOverlaps(decodeUltralyticsOutput(forward(input.image), num_classes_, input, options_),
                          options_.score_threshold, options_.nms_iou);
}

}  // namespace adugs::tracking

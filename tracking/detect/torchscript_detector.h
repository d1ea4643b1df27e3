#pragma once
// ultralytics YOLO11 / YOLOv8 TorchScript exports (`yolo export format=torchscript`, the file
// ending .torchscript) through libtorch: the paper's detector and the recommended path (OpenCV 4.6
// cannot import these models' ONNX exports as written). Input size, class names and task come
// from the archive's config.txt; layout and decoding: tracking/detect/ultralytics_output.h. Built when
// libtorch (Debian libtorch-dev) is present.
#include <memory>
#include <string>

#include "tracking/detect/detector.h"
#include "tracking/detect/ultralytics_output.h"

namespace adugs::tracking {

class TorchScriptDetector : public Detector {
 public:
  // Throws data::InputError naming the file when it is missing, not TorchScript, takes other
  // inputs than one image tensor, or its output does not fit the layout / its class names.
  explicit TorchScriptDetector(const std::string& path, const DetectorOptions& options = {});
  ~TorchScriptDetector() override;
  std::vector<Detection> detect(const cv::Mat& image) override;
  const UltralyticsModelInfo& info() const { return info_; }

 private:
  cv::Mat forward(const cv::Mat& letterboxed);  // the raw output as rows x anchors, CV_32F

  struct Model;
  std::unique_ptr<Model> model_;
  std::string path_;
  DetectorOptions options_;
  UltralyticsModelInfo info_;
  int num_classes_ = 0;
};

}  // namespace adugs::tracking

#pragma once
// ultralytics YOLOv8 / YOLO11 ONNX exports through OpenCV dnn (layout: tracking/detect/ultralytics_output.h).
// OpenCV 4.6 does not import these exports as ultralytics writes them; the graph must first go
// through scripts/prepare_onnx_for_opencv.py (which exports work: that script's header). The
// TorchScript export (tracking/detect/torchscript_detector.h) is the faster and recommended path.
#include <string>

#include <opencv2/dnn.hpp>

#include "tracking/detect/detector.h"
#include "tracking/detect/onnx_signature.h"
#include "tracking/detect/ultralytics_output.h"

namespace adugs::tracking {

class UltralyticsOnnxDetector : public Detector {
 public:
  // `signature` is the file's (read by the factory to choose this backend). Throws
  // data::InputError naming the file when OpenCV cannot import or run it (with the hint to
  // prepare it), or when its output or class names do not fit the layout.
  UltralyticsOnnxDetector(const std::string& onnx_path, const OnnxSignature& signature,
                          const DetectorOptions& options = {});
  std::vector<Detection> detect(const cv::Mat& image) override;
  const UltralyticsModelInfo& info() const { return info_; }

 private:
  cv::Mat forward(const cv::Mat& blob);

  std::string path_;
  DetectorOptions options_;
  UltralyticsModelInfo info_;
  int num_classes_ = 0;
  cv::dnn::Net net_;
};

}  // namespace adugs::tracking

#pragma once
// Darknet YOLO models (.cfg + .weights, e.g. Yolo-Fastest, YOLOv3/v4-tiny) through OpenCV dnn's
// darknet importer. The input is the image resized to the cfg's [net] width x height (no
// letterbox, as darknet itself does), RGB scaled to 0..1. Each [yolo] output row is
// (cx, cy, w, h) relative to the image, objectness, then per-class scores that OpenCV's region
// layer has already multiplied by the objectness; a detection's score is its best class score.
// Classes outside `keep_classes` are dropped; then class-agnostic NMS.
#include <set>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "tracking/detect/detector.h"

namespace adugs::tracking {

struct DarknetOptions {
  double score_threshold = 0.3;
  double nms_iou = 0.45;
  std::set<int> keep_classes = dynamicCocoClasses();
};

// Decoding of the [yolo] output rows for an image of image_size (before NMS).
std::vector<Detection> decodeDarknetOutput(const cv::Mat& rows, const cv::Size& image_size,
                                           const DarknetOptions& options);

class DarknetDetector : public Detector {
 public:
  // Throws data::InputError naming the file when either is missing or OpenCV cannot load them,
  // or when the cfg has no [net] width/height.
  DarknetDetector(const std::string& cfg_path, const std::string& weights_path, const DarknetOptions& options = {});
  std::vector<Detection> detect(const cv::Mat& image) override;
  cv::Size inputSize() const { return input_size_; }

 private:
  DarknetOptions options_;
  cv::dnn::Net net_;
  cv::Size input_size_;
  std::vector<std::string> outputs_;
};

}  // namespace adugs::tracking

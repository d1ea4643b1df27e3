#pragma once
// YOLOX (Megvii) ONNX detector through OpenCV dnn, as exported by YOLOX's tools/export_onnx.py
// without in-graph decoding: input 1x3xSxS (BGR, 0..255, no normalisation), output 1xNx(5+C) per
// anchor of the stride-8/16/32 grids: (x, y) offsets and log (w, h) in grid cells, objectness and
// class probabilities (already sigmoid). Preprocessing is YOLOX's: letterbox resize by
// r = min(S/h, S/w) placed top-left, padding 114.
//   box: cx = (x + gx) * stride / r, w = exp(log w) * stride / r;  score = objectness * class prob.
// Only the classes in `keep_classes` (COCO ids of things that move) are returned, after
// class-agnostic non-maximum suppression.
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <set>
#include <string>
#include <vector>

#include "tracking/detect/detector.h"

namespace adugs::tracking {

struct YoloxOptions {
  int input_size = 416;
  double score_threshold = 0.3;
  double nms_iou = 0.45;
  std::set<int> keep_classes = dynamicCocoClasses();
};

// Decoding of the raw output (rows = anchors, cols = 5 + classes) for an image that was scaled
// by `ratio` into the network input: boxes in original image pixels, thresholded, before NMS.
std::vector<Detection> decodeYoloxOutput(const cv::Mat& output, int input_size, double ratio,
                                         const YoloxOptions& options);

class YoloxDetector : public Detector {
 public:
  // Throws data::InputError naming the file if it is missing or OpenCV cannot load it, or if its
  // output does not have the YOLOX layout for this input size.
  YoloxDetector(const std::string& onnx_path, const YoloxOptions& options = {});
  std::vector<Detection> detect(const cv::Mat& image) override;

 private:
  std::string path_;
  YoloxOptions options_;
  cv::dnn::Net net_;
};

}  // namespace adugs::tracking

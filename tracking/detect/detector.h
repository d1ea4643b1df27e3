#pragma once
// An object detector: an image in, boxes of potentially dynamic objects out (after NMS). The
// backends are chosen from the model file (tracking/detect/detector_factory.h).
#include <set>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/box.h"

namespace adugs::tracking {

// One detected object, in the image's pixels.
struct Detection {
  Box box;
  int class_id = 0;
  double score = 1.0;
  cv::Mat appearance = cv::Mat();  // optional boxHistogram (tracking/sort/appearance.h) for SORT's appearance cue
};

class Detector {
 public:
  virtual ~Detector() = default;
  // image: CV_8UC1 or CV_8UC3 (BGR).
  virtual std::vector<Detection> detect(const cv::Mat& image) = 0;
};

// COCO ids of potentially dynamic objects: person, bicycle, car, motorcycle, bus, train, truck,
// boat, bird, cat, dog, horse, sheep, cow.
const std::set<int>& dynamicCocoClasses();
// Their COCO names ("person", "bicycle", "car", ...).
const std::set<std::string>& dynamicClassNames();
// The ids among a model's class names that name a dynamic class.
std::set<int> dynamicClassIds(const std::vector<std::string>& names);

// What the ultralytics backends are told (YOLOX and darknet keep structs with the same fields).
struct DetectorOptions {
  double score_threshold = 0.3;
  double nms_iou = 0.45;
  // Used when the model file does not name its classes; a model that names them keeps the ids
  // whose names are in dynamicClassNames().
  std::set<int> keep_classes = dynamicCocoClasses();
};

// Class-agnostic non-maximum suppression (the mask needs each object once, and YOLO often reports
// one vehicle as both car and truck): candidates above score_threshold, overlaps above nms_iou
// removed, best score first.
std::vector<Detection> suppressOverlaps(const std::vector<Detection>& candidates, double score_threshold,
                                        double nms_iou);

}  // namespace adugs::tracking

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
// removed, best score first; then dropGroupBoxes.
std::vector<Detection> suppressOverlaps(const std::vector<Detection>& candidates, double score_threshold,
                                        double nms_iou);

// A weak box around a crowd: YOLO sometimes adds, at a low score, one box spanning several people
// it also found one by one (measured: a "train" at 0.35 over 90 % of the image around four people,
// in a simulated room; masked, it left the estimator blind for six frames and reset it). NMS keeps
// it: a big box's IoU with the small boxes inside is small. A detection holding two or more
// detections (each at least kGroupInsideMin of its area inside), all scoring higher, is dropped:
// it is either such a box or one object also found in pieces, which the pieces cover. Any class,
// as the group box's is arbitrary; a vehicle whose people are surer than itself loses its box in
// that frame, and SORT carries it if it is tracked.
constexpr double kGroupInsideMin = 0.8;
std::vector<Detection> dropGroupBoxes(const std::vector<Detection>& detections);

}  // namespace adugs::tracking

#include "tracking/detect/detector.h"

#include <opencv2/dnn.hpp>

namespace adugs::tracking {

const std::set<int>& dynamicCocoClasses() {
  static const std::set<int> classes{0, 1, 2, 3, 5, 6, 7, 8, 14, 15, 16, 17, 18, 19};
  return classes;
}

const std::set<std::string>& dynamicClassNames() {
  static const std::set<std::string> names{"person", "bicycle", "car",   "motorcycle", "bus",
                                           "train",  "truck",   "boat",  "bird",       "cat",
                                           "dog",    "horse",   "sheep", "cow"};
  return names;
}

std::set<int> dynamicClassIds(const std::vector<std::string>& names) {
  std::set<int> ids;
  for (size_t i = 0; i < names.size(); ++i)
    if (dynamicClassNames().count(names[i])) ids.insert(static_cast<int>(i));
  return ids;
}

std::vector<Detection> suppressOverlaps(const std::vector<Detection>& candidates, double score_threshold,
                                        double nms_iou) {
  std::vector<cv::Rect2d> rects;
  std::vector<float> scores;
  for (const Detection& d : candidates) {
    rects.push_back(d.box.rect());
    scores.push_back(static_cast<float>(d.score));
  }
  std::vector<int> keep;
  cv::dnn::NMSBoxes(rects, scores, static_cast<float>(score_threshold), static_cast<float>(nms_iou), keep);
  std::vector<Detection> kept;
  for (int k : keep) kept.push_back(candidates[k]);
  return dropGroupBoxes(kept);
}

std::vector<Detection> dropGroupBoxes(const std::vector<Detection>& detections) {
  std::vector<Detection> kept;
  for (const Detection& group : detections) {
    const cv::Rect2d outer = group.box.rect();
    int members = 0;
    bool all_stronger = true;
    for (const Detection& d : detections) {
      if (&d == &group) continue;
      const cv::Rect2d inner = d.box.rect();
      if (inner.area() <= 0 || (inner & outer).area() < kGroupInsideMin * inner.area()) continue;
      ++members;
      all_stronger = all_stronger && d.score > group.score;
    }
    if (members < 2 || !all_stronger) kept.push_back(group);
  }
  return kept;
}

}  // namespace adugs::tracking

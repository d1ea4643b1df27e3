#pragma once
// The detector backend from the model file: `.onnx` -> YOLOX (OpenCV dnn); `.weights` with its
// `.cfg` (given, or beside the weights with the same name) -> darknet (OpenCV dnn).
// Anything else is an InputError naming the file and the formats that load.
#include <memory>
#include <string>

#include "tracking/detector.h"

namespace adugs::tracking {

std::unique_ptr<Detector> makeDetector(const std::string& model_path, const std::string& config_path = "");

}  // namespace adugs::tracking

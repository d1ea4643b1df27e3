#pragma once
// The detector backend from the model file:
//   .torchscript             ultralytics YOLO11 / YOLOv8 TorchScript export (libtorch; recommended)
//   .onnx                    ultralytics export (output 1 x (4 + C) x N, prepared for OpenCV) or
//                            YOLOX (output 1 x N x (5 + C)), told apart by the output shape
//   .weights (+ .cfg)        darknet, the .cfg given or beside the weights with the same name
// Anything else is an InputError naming the file and the formats that load.
#include <memory>
#include <string>

#include "tracking/detect/detector.h"

namespace adugs::tracking {

std::unique_ptr<Detector> makeDetector(const std::string& model_path, const std::string& config_path = "");

// Whether this build has the libtorch backends (TorchScript detector, MobileSAM): their module
// (tracking/torch_plugin_loader) is there to be loaded.
bool haveTorchBackends();

}  // namespace adugs::tracking

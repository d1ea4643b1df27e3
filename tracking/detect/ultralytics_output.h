#pragma once
// What an ultralytics YOLOv8 / YOLO11 export (ONNX or TorchScript) hands back, and how to read it.
// The detect head's output is 1 x (4 + C) x N, one column per anchor of the stride 8/16/32 grids:
// cx, cy, w, h in network-input pixels, then the C class scores (sigmoid applied, no objectness).
// A segmentation model appends 32 mask coefficients per column (ignored: the box is prompted to
// the project's own segmenter). The input is a centred letterbox (tracking/detect/letterbox.h), RGB / 255.
// The export names its classes and input size in metadata: ONNX metadata_props and the
// TorchScript file's extra file config.txt (JSON), with keys "names" ({0: 'person', ...}),
// "imgsz" ([640, 640] as height, width) and "task" ("detect", "segment", ...).
#include <map>
#include <set>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/detect/detector.h"
#include "tracking/detect/letterbox.h"

namespace adugs::tracking {

struct UltralyticsModelInfo {
  cv::Size input_size;             // width x height; empty when the metadata does not say
  std::vector<std::string> names;  // class names by id; empty when the metadata does not say
  std::string task;                // "detect", "segment", ...; empty when unknown
};

// From the metadata entries (key -> value text: YAML, JSON or a Python literal, as ultralytics
// writes them). Throws data::InputError naming `path` and the key when a present entry is malformed.
UltralyticsModelInfo parseUltralyticsMetadata(const std::map<std::string, std::string>& entries,
                                              const std::string& path);

// The classes to keep for a model with these names: those named as dynamic classes; all of them
// (with a warning on stderr naming `path`) when none is, since for odometry masking too much is
// the safe error; `fallback` when the model does not name its classes.
std::set<int> keptClasses(const UltralyticsModelInfo& info, const std::set<int>& fallback, const std::string& path);

// The class count of an output with `rows` rows: the names' count when known (checked against the
// rows: 4 + C, or 4 + C + 32 for a segmentation model), else rows - 4. Throws data::InputError
// naming `path` when they do not fit.
int ultralyticsClassCount(int rows, const UltralyticsModelInfo& info, const std::string& path);

// Boxes in original image pixels from the output (rows x N, CV_32F), thresholded, before NMS.
// Only classes in options.keep_classes are returned.
std::vector<Detection> decodeUltralyticsOutput(const cv::Mat& output, int num_classes,
                                               const Letterbox& input, const DetectorOptions& options);

}  // namespace adugs::tracking

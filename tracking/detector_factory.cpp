#include "tracking/detector_factory.h"

#include <filesystem>

#include "data/input_error.h"
#include "tracking/darknet_detector.h"
#include "tracking/yolox_detector.h"

namespace adugs::tracking {

std::unique_ptr<Detector> makeDetector(const std::string& model_path, const std::string& config_path) {
  namespace fs = std::filesystem;
  const std::string ext = fs::path(model_path).extension().string();
  if (ext == ".onnx") return std::make_unique<YoloxDetector>(model_path);
  if (ext == ".weights") {
    const std::string cfg = config_path.empty() ? fs::path(model_path).replace_extension(".cfg").string() : config_path;
    return std::make_unique<DarknetDetector>(cfg, model_path);
  }
  throw data::InputError(model_path, 0, "detector_model",
                         "unknown detector model format '" + ext +
                             "' (loads: YOLOX .onnx; darknet .weights with its .cfg)");
}

}  // namespace adugs::tracking

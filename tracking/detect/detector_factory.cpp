#include "tracking/detect/detector_factory.h"

#include <filesystem>

#include "data/input_error.h"
#include "tracking/detect/darknet_detector.h"
#include "tracking/detect/onnx_signature.h"
#include "tracking/detect/ultralytics_onnx_detector.h"
#include "tracking/detect/yolox_detector.h"
#include "tracking/torch_plugin_loader.h"

namespace adugs::tracking {
namespace {

// ultralytics heads put the channels first (1 x 84 x 8400), YOLOX the anchors (1 x 3549 x 85).
bool isUltralyticsLayout(const OnnxSignature& sig) {
  if (sig.metadata.count("names") && sig.metadata.count("imgsz")) return true;
  const OnnxTensorInfo& out = sig.outputs.front();
  return out.dims.size() == 3 && out.dims[1] > 0 && out.dims[2] > 0 && out.dims[1] < out.dims[2];
}

}  // namespace

bool haveTorchBackends() { return !torchModulePath().empty(); }

std::unique_ptr<Detector> makeDetector(const std::string& model_path, const std::string& config_path) {
  namespace fs = std::filesystem;
  const std::string ext = fs::path(model_path).extension().string();
  if (ext == ".onnx") {
    const OnnxSignature sig = readOnnxSignature(model_path);
    if (isUltralyticsLayout(sig)) return std::make_unique<UltralyticsOnnxDetector>(model_path, sig);
    return std::make_unique<YoloxDetector>(model_path);
  }
  if (ext == ".weights") {
    const std::string cfg = config_path.empty() ? fs::path(model_path).replace_extension(".cfg").string() : config_path;
    return std::make_unique<DarknetDetector>(cfg, model_path);
  }
  if (ext == ".torchscript") return makeTorchScriptDetector(model_path);  // libtorch, loaded now
  if (ext == ".pt")
    throw data::InputError(model_path, 0, "detector_model",
                           "a .pt file is an ultralytics training checkpoint (Python pickle), not a "
                           "deployable model: export it with `yolo export model=" +
                               fs::path(model_path).filename().string() + " format=torchscript` and pass the .torchscript file");
  throw data::InputError(model_path, 0, "detector_model",
                         "unknown detector model format '" + ext +
                             "' (loads: ultralytics .torchscript; ultralytics or YOLOX .onnx; darknet .weights "
                             "with its .cfg)");
}

}  // namespace adugs::tracking

#include "tracking/torch_plugin_loader.h"

#include "data/input_error.h"
#include "data/plugin_module.h"
#include "tracking/detect/detector.h"
#include "tracking/segment/box_segmenter.h"
#include "tracking/torch_plugin.h"

namespace adugs::tracking {
namespace {

struct Module {
  MakeTorchDetector make_detector = nullptr;
  MakeMobileSam make_mobilesam = nullptr;
  std::string error;  // why it is not there, when it is not
};

#ifdef ADUGS_TORCH_MODULE_BUILD_PATH
const char* const kBuildPath = ADUGS_TORCH_MODULE_BUILD_PATH;
#else
const char* const kBuildPath = "";
#endif

const Module& module() {
  static const Module m = [] {
    Module out;
    const data::PluginModule& plugin = data::openPluginModule(
        kTorchModuleFile, "ADUGS_TORCH_MODULE", kBuildPath,
        "this adugs was built without libtorch; install Debian's libtorch-dev (scripts/setup.sh "
        "does) and rebuild");
    out.error = plugin.error;
    if (!out.error.empty()) return out;
    out.make_detector = reinterpret_cast<MakeTorchDetector>(plugin.symbol(kMakeTorchDetectorSymbol));
    out.make_mobilesam = reinterpret_cast<MakeMobileSam>(plugin.symbol(kMakeMobileSamSymbol));
    if (!out.make_detector || !out.make_mobilesam)
      out.error = plugin.path + " is not an adugs libtorch module (entry points missing)";
    return out;
  }();
  return m;
}

const Module& requireModule(const std::string& model_path, const std::string& field) {
  const Module& m = module();
  if (!m.error.empty()) throw data::InputError(model_path, 0, field, "TorchScript models need libtorch: " + m.error);
  return m;
}

}  // namespace

std::string torchModulePath() { return data::pluginModulePath(kTorchModuleFile, "ADUGS_TORCH_MODULE", kBuildPath); }

std::unique_ptr<Detector> makeTorchScriptDetector(const std::string& model_path) {
  return std::unique_ptr<Detector>(requireModule(model_path, "detector_model").make_detector(model_path));
}

std::unique_ptr<BoxSegmenter> makeMobileSamSegmenter(const std::string& encoder_path, const std::string& decoder_path) {
  return std::unique_ptr<BoxSegmenter>(requireModule(encoder_path, "sam_encoder").make_mobilesam(encoder_path, decoder_path));
}

}  // namespace adugs::tracking

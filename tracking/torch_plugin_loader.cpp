#include "tracking/torch_plugin_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "data/input_error.h"
#include "tracking/detect/detector.h"
#include "tracking/segment/box_segmenter.h"
#include "tracking/torch_plugin.h"

namespace adugs::tracking {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> candidatePaths() {
  if (const char* env = std::getenv("ADUGS_TORCH_MODULE"); env && *env) return {env};
  std::vector<std::string> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / kTorchModuleFile).string());
#ifdef ADUGS_TORCH_MODULE_BUILD_PATH
  paths.push_back(ADUGS_TORCH_MODULE_BUILD_PATH);
#endif
  return paths;
}

struct Module {
  MakeTorchDetector make_detector = nullptr;
  MakeMobileSam make_mobilesam = nullptr;
  std::string error;  // why it is not there, when it is not
};

// Opened once; never closed (the objects it made may outlive any scope, and libtorch's static
// state does not survive an unload).
const Module& module() {
  static Module m;
  static std::once_flag once;
  std::call_once(once, [] {
    const std::string path = torchModulePath();
    if (path.empty()) {
      m.error = std::string(kTorchModuleFile) + " is not next to the adugs binary" +
                (std::getenv("ADUGS_TORCH_MODULE") ? " nor at $ADUGS_TORCH_MODULE" : "") +
                ": this adugs was built without libtorch; install Debian's libtorch-dev "
                "(scripts/setup.sh does) and rebuild";
      return;
    }
    // RTLD_LOCAL: the module's copies of our helpers stay its own.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      m.error = "cannot open " + path + ": " + dlerror();
      return;
    }
    m.make_detector = reinterpret_cast<MakeTorchDetector>(dlsym(handle, kMakeTorchDetectorSymbol));
    m.make_mobilesam = reinterpret_cast<MakeMobileSam>(dlsym(handle, kMakeMobileSamSymbol));
    if (!m.make_detector || !m.make_mobilesam) m.error = path + " is not an adugs libtorch module (entry points missing)";
  });
  return m;
}

const Module& requireModule(const std::string& model_path, const std::string& field) {
  const Module& m = module();
  if (!m.error.empty()) throw data::InputError(model_path, 0, field, "TorchScript models need libtorch: " + m.error);
  return m;
}

}  // namespace

std::string torchModulePath() {
  for (const std::string& path : candidatePaths()) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return path;
  }
  return "";
}

std::unique_ptr<Detector> makeTorchScriptDetector(const std::string& model_path) {
  return std::unique_ptr<Detector>(requireModule(model_path, "detector_model").make_detector(model_path));
}

std::unique_ptr<BoxSegmenter> makeMobileSamSegmenter(const std::string& encoder_path, const std::string& decoder_path) {
  return std::unique_ptr<BoxSegmenter>(requireModule(encoder_path, "sam_encoder").make_mobilesam(encoder_path, decoder_path));
}

}  // namespace adugs::tracking

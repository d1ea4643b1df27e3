#include "data/media/media_loader.h"

#include "data/input_error.h"
#include "data/plugin_module.h"

namespace adugs::data {
namespace {

#ifdef ADUGS_MEDIA_MODULE_BUILD_PATH
const char* const kBuildPath = ADUGS_MEDIA_MODULE_BUILD_PATH;
#else
const char* const kBuildPath = "";
#endif
const char* const kEnvVar = "ADUGS_MEDIA_MODULE";

struct Module {
  const MediaFunctions* functions = nullptr;
  std::string error;
};

const Module& module() {
  static const Module m = [] {
    Module out;
    const PluginModule& plugin = openPluginModule(
        kMediaModuleFile, kEnvVar, kBuildPath,
        "it is built with adugs (cmake --build build); copy it beside the adugs binary you run");
    out.error = plugin.error;
    if (!out.error.empty()) return out;
    const auto get = reinterpret_cast<GetMediaFunctions>(plugin.symbol(kMediaFunctionsSymbol));
    if (get) out.functions = get();
    if (!out.functions) out.error = plugin.path + " is not an adugs media module (entry point missing)";
    return out;
  }();
  return m;
}

}  // namespace

const MediaFunctions& requireMediaModule(const std::string& path, const std::string& field,
                                         const std::string& needed_for) {
  const Module& m = module();
  if (!m.functions) throw InputError(path, 0, field, needed_for + " need " + kMediaModuleFile + ": " + m.error);
  return *m.functions;
}

std::string mediaModulePath() { return pluginModulePath(kMediaModuleFile, kEnvVar, kBuildPath); }

}  // namespace adugs::data

#include "data/plugin_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

namespace adugs::data {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> candidatePaths(const std::string& file_name, const std::string& env_var,
                                        const std::string& build_path) {
  if (const char* env = std::getenv(env_var.c_str()); env && *env) return {env};
  std::vector<std::string> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / file_name).string());
  if (!build_path.empty()) paths.push_back(build_path);
  return paths;
}

}  // namespace

void* PluginModule::symbol(const char* name) const {
  return handle ? dlsym(handle, name) : nullptr;
}

std::string pluginModulePath(const std::string& file_name, const std::string& env_var,
                             const std::string& build_path) {
  for (const std::string& path : candidatePaths(file_name, env_var, build_path)) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return path;
  }
  return "";
}

const PluginModule& openPluginModule(const std::string& file_name, const std::string& env_var,
                                     const std::string& build_path, const std::string& missing_hint) {
  static std::mutex mutex;
  static std::map<std::string, PluginModule> opened;  // nodes never move: references stay valid
  std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = opened.find(file_name); it != opened.end()) return it->second;
  PluginModule& m = opened[file_name];
  m.path = pluginModulePath(file_name, env_var, build_path);
  if (m.path.empty()) {
    m.error = file_name + " is not next to the adugs binary" +
              (std::getenv(env_var.c_str()) ? " nor at $" + env_var : std::string()) + ": " + missing_hint;
    return m;
  }
  // RTLD_LOCAL: the module's copies of our helpers stay its own.
  m.handle = dlopen(m.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!m.handle) m.error = "cannot open " + m.path + ": " + dlerror();
  return m;
}

}  // namespace adugs::data

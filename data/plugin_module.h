#pragma once
// Optional parts of adugs live in modules (shared objects opened with dlopen) so that a command
// that does not use them does not load their libraries: libtorch (tracking/torch_plugin.h) and
// OpenCV's video and image-codec libraries (data/media/media_module.h). A module is opened the
// first time it is needed and stays open for the life of the process (objects it made may
// outlive any scope, and its libraries' static state does not survive an unload).
#include <string>

namespace adugs::data {

struct PluginModule {
  void* handle = nullptr;
  std::string path;   // where it was opened from
  std::string error;  // why it is not there, when it is not ("" when open)
  // The entry point `name`, or nullptr when the module is not open or lacks it.
  void* symbol(const char* name) const;
};

// Opens file_name (once per process; later calls return the same result). Where it looks,
// first match: $env_var (a path; when set, the only place looked at), next to the running
// executable (the build writes modules beside app/adugs), then build_path (where this build
// wrote it: for the test executables; "" for none). `missing_hint` ends the error when the
// file is found nowhere (how to get it).
const PluginModule& openPluginModule(const std::string& file_name, const std::string& env_var,
                                     const std::string& build_path, const std::string& missing_hint);

// Where file_name would be opened from ("" when nowhere), without opening it.
std::string pluginModulePath(const std::string& file_name, const std::string& env_var,
                             const std::string& build_path);

}  // namespace adugs::data

#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <sys/wait.h>

#include <gtest/gtest.h>

namespace adugs::test {
namespace fs = std::filesystem;

fs::path sharedDataDir() {
  if (const char* env = std::getenv("ADUGS_SHARED_DATA")) return fs::path(env);
  return fs::path(ADUGS_DEFAULT_SHARED_DIR) / "data";
}

fs::path sharedModelsDir() {
  if (const char* env = std::getenv("ADUGS_SHARED_MODELS")) return fs::path(env);
  return sharedDataDir().parent_path() / "models";
}

TempDir::TempDir(const std::string& prefix) {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path p = fs::temp_directory_path() / (prefix + "_" + std::to_string(rd()));
    if (fs::create_directory(p)) {
      path_ = p;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void writeText(const fs::path& file, const std::string& text) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string readFirstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

int runAdugs(const std::string& args, std::string* output) {
  return runCommand(std::string(ADUGS_BINARY) + " " + args, output);
}

int writeTestBag(const std::string& args, std::string* output) {
  return runCommand(std::string("/usr/bin/python3 ") + ADUGS_SOURCE_DIR +
                        "/tests/data/scripts/write_test_bag.py " + args,
                    output);
}

const fs::path& pythonGenerated(const std::string& script) {
  static std::map<std::string, std::unique_ptr<TempDir>> done;
  static const fs::path none;
  if (const auto it = done.find(script); it != done.end()) return it->second ? it->second->path() : none;
  auto dir = std::make_unique<TempDir>("adugs_generated");
  std::string log;
  const std::string command = "/usr/bin/python3 " + std::string(ADUGS_SOURCE_DIR) + "/" + script + " " + dir->path().string();
  if (runCommand(command, &log) != 0) {
    ADD_FAILURE() << script << " failed (needs /usr/bin/python3 with Debian's python3-torch and python3-onnx: run "
                  << "scripts/setup.sh):\n" << log;
    done[script] = nullptr;
    return none;
  }
  return (done[script] = std::move(dir))->path();
}

int runCommand(const std::string& command, std::string* output) {
  std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf{};
  std::string out;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace adugs::test

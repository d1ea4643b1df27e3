#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <random>
#include <chrono>
#include <csignal>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "data/camera_model.h"
#include "data/input_error.h"

#include <gtest/gtest.h>

#include "data/formats/csv_reader.h"

namespace adugs::test {
namespace fs = std::filesystem;

bool inputsRequired() {
  const char* ci = std::getenv("CI");
  const char* required = std::getenv("ADUGS_REQUIRE_INPUTS");
  return (ci && std::string(ci) == "true") || (required && std::string(required) == "1");
}

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

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string summaryText(const fs::path& summary, const std::string& key) {
  const std::string text = "\n" + readFile(summary);
  const size_t at = text.find("\n" + key + ": ");
  if (at == std::string::npos) return "";
  const size_t from = at + key.size() + 3;
  return text.substr(from, text.find('\n', from) - from);
}

double summaryNumber(const fs::path& summary, const std::string& key) {
  const std::string v = summaryText(summary, key);
  EXPECT_FALSE(v.empty()) << key << " missing in " << summary;
  return v.empty() ? -1 : std::stod(v);
}

size_t csvRows(const fs::path& p) {
  data::CsvReader r(p.string());
  size_t n = 0;
  while (r.next()) ++n;
  return n;
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

AdugsProcess::AdugsProcess(const std::string& args, const fs::path& log) {
  std::vector<std::string> words = {ADUGS_BINARY};
  std::istringstream in(args);
  for (std::string w; in >> w;) words.push_back(w);
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {  // the child: only async-signal-safe calls until exec
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
}

AdugsProcess::AdugsProcess(const std::function<int()>& body, const fs::path& log) {
  std::fflush(nullptr);
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    int code = 2;
    try {
      code = body();
    } catch (const std::exception& e) {
      std::cerr << "adugs: error: " << e.what() << "\n";
    }
    std::cout << std::flush;
    std::cerr << std::flush;
    _exit(code);
  }
}

AdugsProcess::~AdugsProcess() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

void AdugsProcess::signal(int sig) {
  if (pid_ > 0) kill(pid_, sig);
}

int AdugsProcess::wait(std::chrono::seconds timeout) {
  if (pid_ <= 0) return -1;
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (true) {
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      pid_ = -1;
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
      return -1;
    }
    if (std::chrono::steady_clock::now() >= until) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
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

void expectInputError(const std::function<void()>& f, const std::vector<std::string>& fragments) {
  try {
    f();
    ADD_FAILURE() << "no data::InputError thrown";
  } catch (const data::InputError& e) {
    for (const std::string& s : fragments)
      EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what() << "\nlacks: " << s;
  }
}

bool samePixels(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  return a.empty() || cv::norm(a, b, cv::NORM_INF) == 0;
}

std::array<double, 8> paramsOf(const data::CameraModel& cam) {
  const auto& k = cam.coeffs();
  return {cam.fx(), cam.fy(), cam.cx(), cam.cy(), k[0], k[1], k[2], k[3]};
}

}  // namespace adugs::test

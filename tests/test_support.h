#pragma once
// Helpers shared by the test suites: where the shared real data lives, temp folders, running adugs.
#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace cv {
class Mat;
}
namespace adugs::data {
class CameraModel;
}

namespace adugs::test {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The repository's root (the build's ADUGS_SOURCE_DIR).
inline const std::string kSourceDir = ADUGS_SOURCE_DIR;

// Expects data::InputError from f whose message contains every given fragment.
void expectInputError(const std::function<void()>& f, const std::vector<std::string>& fragments);

// Same size, type and every pixel (two empty images are the same).
bool samePixels(const cv::Mat& a, const cv::Mat& b);

// [fu fv pu pv d0..d3], the camera model templates' parameter block.
std::array<double, 8> paramsOf(const data::CameraModel& cam);

// ../shared (or $ADUGS_SHARED_DATA/.. semantics: $ADUGS_SHARED_DATA points at shared/data).
std::filesystem::path sharedDataDir();    // .../shared/data
std::filesystem::path sharedModelsDir();  // .../shared/models

// Whether a test whose inputs are missing (shared data, models, a Debian package's files, the
// built binary) must fail rather than skip: under CI (CI=true, as `.ci/run` is run) or
// ADUGS_REQUIRE_INPUTS=1. A user's fresh clone without ../shared still skips, with the message.
bool inputsRequired();

// Skips the current test with `message`, or fails it when inputsRequired(). Use as
//   ADUGS_SKIP_OR_FAIL("opencv-doc not installed");
#define ADUGS_SKIP_OR_FAIL(message)                                                   \
  do {                                                                                \
    if (adugs::test::inputsRequired()) FAIL() << message << " (required: CI=true)"; \
    GTEST_SKIP() << message;                                                          \
  } while (0)

// Skips (or, under CI, fails) the current test with a clear message when the shared path is
// absent. Use as
//   ADUGS_REQUIRE_SHARED(path);
#define ADUGS_REQUIRE_SHARED(path)                                                             \
  do {                                                                                         \
    if (!std::filesystem::exists(path))                                                        \
      ADUGS_SKIP_OR_FAIL("shared data not found at "                                           \
                         << (path) << " (set ADUGS_SHARED_DATA to the shared/data folder)");   \
  } while (0)

// OpenCV's pedestrian video (Debian's opencv-doc; PETS09-S2L1, 795 frames at 7 fps, a static
// camera over a square): the tests' real video.
inline const std::string kPedestrianVideo = "/usr/share/doc/opencv-doc/examples/data/vtest.avi";

// Skips (or, under CI, fails) the current test when the pedestrian video is not installed.
#define ADUGS_REQUIRE_PEDESTRIAN_VIDEO()                                                           \
  do {                                                                                             \
    if (!std::filesystem::exists(adugs::test::kPedestrianVideo))                                   \
      ADUGS_SKIP_OR_FAIL(adugs::test::kPedestrianVideo << " missing: run scripts/setup.sh (package opencv-doc)"); \
  } while (0)

// A fresh empty directory under the system temp dir, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "adugs_test");
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Writes text to a file (creating parent directories).
void writeText(const std::filesystem::path& file, const std::string& text);
// The first line of a file, without its newline ("" when it cannot be read), e.g. a sysfs attribute.
std::string readFirstLine(const std::filesystem::path& file);
// The whole file ("" when it cannot be read).
std::string readFile(const std::filesystem::path& file);
// The text after "KEY: " on its line of a summary.yaml / record.yaml ("" when absent), and as a
// number (a test failure when absent).
std::string summaryText(const std::filesystem::path& summary, const std::string& key);
double summaryNumber(const std::filesystem::path& summary, const std::string& key);
// Rows of a CSV file after its header.
size_t csvRows(const std::filesystem::path& file);

// Runs a shell command; returns its exit code; stdout+stderr go to *output.
int runCommand(const std::string& command, std::string* output);
// The folder that `/usr/bin/python3 ADUGS_SOURCE_DIR/script OUT_DIR` filled, run once per test
// process and script (test models generated with Debian's python3-torch / python3-onnx); an
// empty path after an ADD_FAILURE naming the script when it failed.
const std::filesystem::path& pythonGenerated(const std::string& script);
// Runs the built `adugs` binary with args; returns exit code; stdout+stderr go to *output.
int runAdugs(const std::string& args, std::string* output);
// The built `adugs` binary as a running process (fork + exec, no shell), for tests that signal it:
// args are split on spaces; stdout and stderr go to `log`. The destructor kills (SIGKILL) and
// reaps it if it still runs.
class AdugsProcess {
 public:
  AdugsProcess(const std::string& args, const std::filesystem::path& log);
  // Or the product's code in a forked child of this test (for a command on a fake kernel layer):
  // `body` runs there, its return value is the exit code (an exception: its message, exit 2).
  // Fork only from a test that has started no thread yet.
  AdugsProcess(const std::function<int()>& body, const std::filesystem::path& log);
  ~AdugsProcess();
  AdugsProcess(const AdugsProcess&) = delete;
  AdugsProcess& operator=(const AdugsProcess&) = delete;
  void signal(int sig);
  // Waits up to `timeout` for the process to end: its exit code, 128 + the signal that ended it,
  // or -1 when it still runs.
  int wait(std::chrono::seconds timeout);
  bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

// Writes a ROS1 bag from an ASL folder with Debian's python3-rosbag
// (tests/data/scripts/write_test_bag.py ARGS: ASL OUT.bag --layout ... [--compression ...]).
int writeTestBag(const std::string& args, std::string* output);

}  // namespace adugs::test

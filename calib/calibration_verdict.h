#pragma once
// The verdict every calibration result carries (intrinsics, camera-IMU, IMU noise):
//   ok      the checks passed; the result is written;
//   weak    written, with a prominent WARNING on stdout, in the report and as a comment in the
//           YAML, listing what is poorly determined and what to record next;
//   failed  nothing is written; the reason is printed and the command exits with code 3
//           (kExitCalibrationFailed; input errors exit with 2).
// Each command's checks live beside it (intrinsics_verdict, camera_imu_verdict, the Allan
// checks in allan_variance); this file holds what they share.
#include <stdexcept>
#include <string>
#include <vector>

namespace adugs::calib {

enum class Verdict { kOk = 0, kWeak = 1, kFailed = 2 };

// "ok", "weak", "failed".
const char* verdictName(Verdict verdict);

constexpr int kExitCalibrationFailed = 3;

struct VerdictFinding {
  Verdict level = Verdict::kWeak;  // kWeak or kFailed
  std::string check;               // short name of the check, e.g. "coverage"
  std::string what;                // measured value against its bound, in words
};

struct CalibrationVerdict {
  Verdict verdict = Verdict::kOk;
  std::vector<VerdictFinding> findings;
  std::vector<std::string> record_next;  // advice, without duplicates, in the order added

  // Adds a finding (level kWeak or kFailed) and raises the verdict to at least that level;
  // advice (optional) goes to record_next once.
  void add(Verdict level, const std::string& check, const std::string& what,
           const std::string& advice = "");
  bool has(const std::string& check) const;
};

// The verdict as a block of text for stdout and the report. ok: one line. weak / failed: a
// framed WARNING / FAILED block listing the findings and what to record next.
std::string formatVerdict(const CalibrationVerdict& verdict, const std::string& what_was_done);

// Why a failed verdict failed, in one line: its failed findings (not the weak ones), "; "-joined.
std::string failureReasons(const CalibrationVerdict& verdict);

// The same as YAML comment lines ("# ..."), for the top of a written calibration file.
std::string verdictYamlComment(const CalibrationVerdict& verdict);

// The verdict a calibration file written by adugs states on its first line ("# verdict: weak"; in
// an EuRoC sensor.yaml the line after "%YAML:1.0"); kOk for "ok" and for a file without that line
// (written by another tool). An unreadable file is an InputError naming it.
Verdict writtenVerdict(const std::string& path);
// Those of the files whose written verdict is weak, in order.
std::vector<std::string> filesMarkedWeak(const std::vector<std::string>& files);
// The summary line naming them, `calibration_weak: ["a", "b"]` + newline; "" when there are none.
std::string calibrationWeakYamlLine(const std::vector<std::string>& weak_files);

// Thrown by a command whose result failed its verdict; main() prints it and exits with
// kExitCalibrationFailed. The message is the formatted verdict.
class CalibrationFailed : public std::runtime_error {
 public:
  explicit CalibrationFailed(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace adugs::calib

#include "calib/calibration_verdict.h"

#include <algorithm>
#include <fstream>

#include "data/input_error.h"

namespace adugs::calib {

const char* verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kOk: return "ok";
    case Verdict::kWeak: return "weak";
    case Verdict::kFailed: return "failed";
  }
  return "?";
}

void CalibrationVerdict::add(Verdict level, const std::string& check, const std::string& what,
                             const std::string& advice) {
  if (level == Verdict::kOk) return;
  findings.push_back({level, check, what});
  verdict = std::max(verdict, level);
  if (!advice.empty() && std::find(record_next.begin(), record_next.end(), advice) == record_next.end())
    record_next.push_back(advice);
}

bool CalibrationVerdict::has(const std::string& check) const {
  return std::any_of(findings.begin(), findings.end(),
                     [&](const VerdictFinding& f) { return f.check == check; });
}

std::string formatVerdict(const CalibrationVerdict& v, const std::string& what_was_done) {
  if (v.verdict == Verdict::kOk) return "Verdict: ok (every check passed)\n";
  const std::string rule(78, '=');
  std::string s = rule + "\n";
  if (v.verdict == Verdict::kWeak)
    s += "WARNING: verdict WEAK. " + what_was_done +
         " was written, but the data do not pin it down:\n";
  else
    s += "FAILED: verdict FAILED. Nothing was written; the result cannot be trusted:\n";
  for (Verdict level : {Verdict::kFailed, Verdict::kWeak})  // the reasons it failed first
    for (const VerdictFinding& f : v.findings)
      if (f.level == level)
        s += std::string("  - [") + verdictName(f.level) + "] " + f.check + ": " + f.what + "\n";
  if (!v.record_next.empty()) {
    s += "Record next:\n";
    for (const std::string& a : v.record_next) s += "  * " + a + "\n";
  }
  s += rule + "\n";
  return s;
}

std::string failureReasons(const CalibrationVerdict& v) {
  std::string s;
  for (const VerdictFinding& f : v.findings)
    if (f.level == Verdict::kFailed) s += (s.empty() ? "" : "; ") + f.what;
  return s.empty() ? "no reason given" : s;
}

std::string verdictYamlComment(const CalibrationVerdict& v) {
  std::string s = std::string("# verdict: ") + verdictName(v.verdict) + "\n";
  if (v.verdict == Verdict::kOk) return s;
  s += "# WARNING: this calibration is WEAK; the data do not pin it down:\n";
  for (const VerdictFinding& f : v.findings) s += "#   - " + f.check + ": " + f.what + "\n";
  if (!v.record_next.empty()) {
    s += "# Record next:\n";
    for (const std::string& a : v.record_next) s += "#   * " + a + "\n";
  }
  return s;
}

Verdict writtenVerdict(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw data::InputError(path, 0, "", "cannot open");
  std::string first;
  std::getline(in, first);
  if (first.rfind("%YAML:", 0) == 0) std::getline(in, first);  // an EuRoC sensor.yaml's header
  return first.rfind("# verdict: weak", 0) == 0 ? Verdict::kWeak : Verdict::kOk;
}

std::vector<std::string> filesMarkedWeak(const std::vector<std::string>& files) {
  std::vector<std::string> weak;
  for (const std::string& file : files)
    if (writtenVerdict(file) == Verdict::kWeak) weak.push_back(file);
  return weak;
}

std::string calibrationWeakYamlLine(const std::vector<std::string>& weak_files) {
  if (weak_files.empty()) return "";
  std::string line = "calibration_weak: [";
  for (size_t i = 0; i < weak_files.size(); ++i) line += (i ? ", \"" : "\"") + weak_files[i] + "\"";
  return line + "]\n";
}

}  // namespace adugs::calib

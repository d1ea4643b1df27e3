#include "data/formats/trajectory_io.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "data/formats/csv_reader.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {

// Beyond this many seconds a time in nanoseconds no longer fits comfortably in int64.
constexpr double kMaxAbsSeconds = 9.0e9;

const std::vector<std::string> kEurocColumns = {"timestamp", "p_x",  "p_y",  "p_z",  "q_w", "q_x",
                                                "q_y",       "q_z",  "v_x",  "v_y",  "v_z", "bw_x",
                                                "bw_y",      "bw_z", "ba_x", "ba_y", "ba_z"};
const std::vector<std::string> kTumColumns = {"timestamp", "tx", "ty", "tz",
                                              "qx",        "qy", "qz", "qw"};

bool parsesAsNumber(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

// Seconds -> nanoseconds. Plain decimals ("1403715273.262142976") are converted digit by digit so
// that 9 decimals survive exactly (a double only holds ~16 significant digits); anything else
// (exponents) goes through a double.
int64_t secondsAt(const CsvReader& row, size_t column) {
  const std::string& s = row.field(column);
  size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  const bool negative = !s.empty() && s[0] == '-';
  size_t int_begin = i;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
  size_t int_end = i;
  std::string frac;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) frac += s[i++];
  }
  const bool plain =
      i == s.size() && (int_end > int_begin || !frac.empty()) && int_end - int_begin <= 10;
  if (!plain) {
    double t = row.doubleAt(column);  // throws on non-numeric and non-finite values
    if (std::abs(t) >= kMaxAbsSeconds)
      row.fail(column,
               "time " + s + " s is out of range (nanoseconds in a TUM file? TUM uses seconds)");
    return secToNs(t);
  }
  int64_t sec = int_end > int_begin ? std::stoll(s.substr(int_begin, int_end - int_begin)) : 0;
  if (sec >= static_cast<int64_t>(kMaxAbsSeconds))
    row.fail(column,
             "time " + s + " s is out of range (nanoseconds in a TUM file? TUM uses seconds)");
  int64_t ns = 0;
  for (size_t k = 0; k < 9; ++k) ns = ns * 10 + (k < frac.size() ? frac[k] - '0' : 0);
  if (frac.size() > 9 && frac[9] >= '5') ++ns;  // round half up on the 10th decimal
  int64_t total = sec * 1000000000LL + ns;
  return negative ? -total : total;
}

void checkQuaternion(const CsvReader& row, Eigen::Quaterniond* q) {
  double norm = q->norm();
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf),
                  "norm is %.6g, not 1 (tolerance %g): wrong column order or not a rotation?", norm,
                  kQuaternionNormTolerance);
    throw InputError(row.path(), row.lineNumber(), "quaternion", buf);
  }
  q->normalize();
}

Eigen::Vector3d vectorAt(const CsvReader& row, size_t first) {
  return {row.doubleAt(first), row.doubleAt(first + 1), row.doubleAt(first + 2)};
}

// Parses the current row into *state. `columns` is the field count of the first data row.
void parseEurocRow(const CsvReader& row, size_t columns, GroundTruthState* state) {
  row.requireColumns(8, 17);
  if (row.size() != 8 && row.size() != 17)
    row.failRow("expected 8 (t,p,q) or 17 (t,p,q,v,bw,ba) fields, found " +
                std::to_string(row.size()) + " (truncated or malformed line?)");
  if (row.size() != columns)
    row.failRow("has " + std::to_string(row.size()) + " fields but the first data line has " +
                std::to_string(columns) + " (truncated line?)");
  state->pose.t_ns = row.int64At(0);
  state->pose.p_W_B = vectorAt(row, 1);
  Eigen::Quaterniond q(row.doubleAt(4), row.doubleAt(5), row.doubleAt(6),
                       row.doubleAt(7));  // w first
  checkQuaternion(row, &q);
  state->pose.q_W_B = q;
  state->has_velocity_and_biases = row.size() == 17;
  if (state->has_velocity_and_biases) {
    state->v_W = vectorAt(row, 8);
    state->gyro_bias = vectorAt(row, 11);
    state->accel_bias = vectorAt(row, 14);
  }
}

void parseTumRow(const CsvReader& row, GroundTruthState* state) {
  row.requireColumns(8);
  state->pose.t_ns = secondsAt(row, 0);
  state->pose.p_W_B = vectorAt(row, 1);
  Eigen::Quaterniond q(row.doubleAt(7), row.doubleAt(4), row.doubleAt(5),
                       row.doubleAt(6));  // w last
  checkQuaternion(row, &q);
  state->pose.q_W_B = q;
  state->has_velocity_and_biases = false;
}

std::vector<GroundTruthState> readStates(const std::string& path, TrajectoryReadInfo* info) {
  const TrajectoryFormat format = detectTrajectoryFormat(path);
  TrajectoryReadInfo local;
  if (!info) info = &local;
  *info = TrajectoryReadInfo{};
  info->format = format;
  const bool euroc = format == TrajectoryFormat::kEurocCsv;
  CsvReader row(path, euroc ? CsvReader::Separator::kComma : CsvReader::Separator::kWhitespace);
  row.setColumnNames(euroc ? kEurocColumns : kTumColumns);

  std::vector<GroundTruthState> states;
  size_t columns = 0;
  long previous_line = 0;
  bool first_row = true;
  while (row.next()) {
    if (first_row) {
      first_row = false;
      if (!parsesAsNumber(row.field(0))) continue;  // a header line without '#'
    }
    if (columns == 0) columns = row.size();
    GroundTruthState state;
    if (euroc) {
      parseEurocRow(row, columns, &state);
    } else {
      parseTumRow(row, &state);
    }
    if (!states.empty()) {
      int64_t previous = states.back().pose.t_ns;
      if (state.pose.t_ns == previous) {  // keep the first pose of a stamp, drop and count this
        if (info->duplicates_dropped++ == 0) info->first_duplicate_line = row.lineNumber();
        continue;
      }
      if (state.pose.t_ns < previous)
        throw InputError(path, row.lineNumber(), "timestamp",
                         "time goes backwards: " + std::to_string(state.pose.t_ns) + " ns after " +
                             std::to_string(previous) + " ns at line " +
                             std::to_string(previous_line) + " (timestamps must be increasing)");
    }
    previous_line = row.lineNumber();
    states.push_back(state);
  }
  if (states.empty())
    throw InputError(path, 0, "", "no poses in file (empty, or only comments and a header)");
  return states;
}

Trajectory posesOf(const std::vector<GroundTruthState>& states) {
  Trajectory trajectory;
  trajectory.reserve(states.size());
  for (const GroundTruthState& s : states) trajectory.push_back(s.pose);
  return trajectory;
}

}  // namespace

const char* trajectoryFormatName(TrajectoryFormat format) {
  return format == TrajectoryFormat::kEurocCsv ? "EuRoC CSV" : "TUM";
}

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  CsvReader row(path, CsvReader::Separator::kComma);
  if (!row.next()) throw InputError(path, 0, "", "no poses in file (empty, or only comments)");
  return row.size() > 1 ? TrajectoryFormat::kEurocCsv : TrajectoryFormat::kTum;
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat* format) {
  TrajectoryReadInfo info;
  Trajectory trajectory = posesOf(readStates(path, &info));
  if (format) *format = info.format;
  return trajectory;
}

Trajectory readTrajectory(const std::string& path, TrajectoryReadInfo* info) {
  return posesOf(readStates(path, info));
}

std::vector<GroundTruthState> readGroundTruthStates(const std::string& path,
                                                    TrajectoryReadInfo* info) {
  return readStates(path, info);
}

std::string formatTumLine(const StampedPose& pose) {
  const bool negative = pose.t_ns < 0;
  const uint64_t abs_ns =
      negative ? 0 - static_cast<uint64_t>(pose.t_ns) : static_cast<uint64_t>(pose.t_ns);
  const Eigen::Vector3d& p = pose.p_W_B;
  const Eigen::Quaterniond& q = pose.q_W_B;
  char buf[320];
  std::snprintf(buf, sizeof(buf), "%s%llu.%09llu %.17g %.17g %.17g %.17g %.17g %.17g %.17g",
                negative ? "-" : "", static_cast<unsigned long long>(abs_ns / 1000000000ULL),
                static_cast<unsigned long long>(abs_ns % 1000000000ULL), p.x(), p.y(), p.z(), q.x(),
                q.y(), q.z(), q.w());
  return buf;
}

TumTrajectoryWriter::TumTrajectoryWriter(const std::string& path)
    : path_(path), out_(path, std::ios::trunc) {
  if (!out_) throw InputError(path, 0, "", "cannot open file for writing");
  out_ << "# timestamp[s] tx ty tz qx qy qz qw (T_W_B: body B in world W)\n" << std::flush;
  if (!out_) throw InputError(path, 0, "", "write failed");
}

void TumTrajectoryWriter::write(const StampedPose& pose) {
  if (count_ > 0 && pose.t_ns <= last_t_ns_)
    throw std::invalid_argument("TumTrajectoryWriter(" + path_ + "): time " +
                                std::to_string(pose.t_ns) + " ns is not after the previous pose (" +
                                std::to_string(last_t_ns_) + " ns)");
  if (!pose.p_W_B.allFinite() || !pose.q_W_B.coeffs().allFinite())
    throw std::invalid_argument("TumTrajectoryWriter(" + path_ + "): non-finite pose at " +
                                std::to_string(pose.t_ns) + " ns");
  out_ << formatTumLine(pose) << '\n' << std::flush;
  if (!out_) throw InputError(path_, 0, "", "write failed");
  last_t_ns_ = pose.t_ns;
  ++count_;
}

void TumTrajectoryWriter::close() {
  if (!out_.is_open()) return;
  out_.flush();
  bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) throw InputError(path_, 0, "", "write failed");
}

TumTrajectoryWriter::~TumTrajectoryWriter() {
  try {
    close();
  } catch (...) {
  }
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  const std::string tmp = path + ".tmp";
  try {
    TumTrajectoryWriter writer(tmp);
    for (const StampedPose& pose : trajectory) writer.write(pose);
    writer.close();
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError(path, 0, "", "cannot rename " + tmp + " to it: " + ec.message());
}

}  // namespace adugs::data

#pragma once
// Trajectory files in and out.
//
// Readers auto-detect the two formats used around the project:
//   EuRoC ground-truth CSV  comma separated, time in integer nanoseconds, quaternion w FIRST:
//                           t,px,py,pz,qw,qx,qy,qz                       (8 columns), or
//                           t,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz (17 columns)
//   TUM                     whitespace separated, time in seconds, quaternion w LAST:
//                           t tx ty tz qx qy qz qw
// The first data line decides: a comma means EuRoC CSV, otherwise TUM. '#' lines and blank lines
// are skipped; a first line whose first field starts with a letter is taken as a header.
// Every pose is checked: finite values, quaternion norm within kQuaternionNormTolerance of 1
// (then normalised), increasing time, a consistent column count. Errors are InputError naming the
// file, line and field.
// Exact duplicate timestamps (the same nanosecond on consecutive poses, as in some published
// third-party estimates) are accepted: the FIRST pose of each stamp is kept, the later ones are
// dropped and counted in TrajectoryReadInfo. Time going backwards stays an error. So every
// trajectory returned is strictly increasing in time.
//
// The writer produces TUM (what `evo` reads): seconds with 9 decimals (exact nanoseconds) and 17
// significant digits for the values, flushed line by line so that a killed run keeps its poses.
#include <fstream>
#include <string>
#include <vector>

#include "data/types.h"

namespace adugs::data {

enum class TrajectoryFormat { kEurocCsv, kTum };

// |‖q‖ - 1| above this is an error; below it the quaternion is normalised.
constexpr double kQuaternionNormTolerance = 1e-2;

// "EuRoC CSV" or "TUM".
const char* trajectoryFormatName(TrajectoryFormat format);

// What a reader saw besides the poses.
struct TrajectoryReadInfo {
  TrajectoryFormat format = TrajectoryFormat::kTum;
  size_t duplicates_dropped = 0;  // poses dropped because their stamp equals the previous one
  long first_duplicate_line = 0;  // file line of the first dropped pose (0: none)
};

// Looks at the first data line. Throws InputError if the file is missing or has no data line.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

// Reads the poses (T_W_B) of a trajectory file. `format`, if given, receives the detected format.
// Throws InputError on any invalid content, and if the file holds no pose.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat* format = nullptr);
// The same, reporting the format and the dropped duplicates in *info (if not null).
Trajectory readTrajectory(const std::string& path, TrajectoryReadInfo* info);

// As readTrajectory, keeping velocity and biases when the file has them (17-column EuRoC CSV).
std::vector<GroundTruthState> readGroundTruthStates(const std::string& path,
                                                    TrajectoryReadInfo* info = nullptr);

// One TUM line "t tx ty tz qx qy qz qw" (no newline), t = seconds with exactly 9 decimals.
std::string formatTumLine(const StampedPose& pose);

// Appends poses to a TUM file, one flushed line per pose. The constructor truncates the file and
// writes a '#' header; it throws InputError if the file cannot be opened. Poses must come in
// strictly increasing time (std::invalid_argument otherwise), so the file reads back.
class TumTrajectoryWriter {
 public:
  explicit TumTrajectoryWriter(const std::string& path);

  void write(const StampedPose& pose);
  // Flushes and closes; throws InputError if the stream went bad. Also called by the destructor
  // (which swallows errors).
  void close();
  ~TumTrajectoryWriter();

  TumTrajectoryWriter(const TumTrajectoryWriter&) = delete;
  TumTrajectoryWriter& operator=(const TumTrajectoryWriter&) = delete;

  const std::string& path() const { return path_; }
  size_t count() const { return count_; }

 private:
  std::string path_;
  std::ofstream out_;
  size_t count_ = 0;
  int64_t last_t_ns_ = 0;
};

// Writes a whole trajectory atomically: to `path`.tmp, then renamed over `path`.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory);

}  // namespace adugs::data

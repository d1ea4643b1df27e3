#include "data/sources/euroc_reader.h"

#include <filesystem>
#include <iostream>


#include "data/formats/csv_reader.h"
#include "data/formats/image_file.h"
#include "data/input_error.h"

namespace adugs::data {
namespace fs = std::filesystem;
namespace {

fs::path requireDir(const fs::path& p) {
  std::error_code ec;
  if (fs::is_directory(p, ec)) return p;
  throw InputError(p.string(), 0, "", fs::exists(p, ec) ? "is not a folder" : "folder not found");
}

std::string requireFile(const fs::path& p) {
  std::error_code ec;
  if (fs::is_regular_file(p, ec)) return p.string();
  throw InputError(p.string(), 0, "", fs::exists(p, ec) ? "is not a regular file" : "file not found");
}

// "timestamp 5 on line 7 is not after 9 on line 6"
void requireIncreasing(const CsvReader& csv, int64_t t, int64_t prev_t, long prev_line) {
  if (prev_line == 0 || t > prev_t) return;
  std::string what = t == prev_t ? "duplicate timestamp " : "timestamp goes backwards: ";
  csv.fail(0, what + std::to_string(t) + " is not after " + std::to_string(prev_t) + " on line " +
                  std::to_string(prev_line));
}

}  // namespace

EurocReader::EurocReader(const std::string& root_dir, EurocReaderOptions options,
                         EurocCalibrationOverride calibration)
    : options_(options),
      image_time_shift_ns_(calibration.image_time_shift_ns),
      calibration_source_(calibration.camera ? "the given camera calibration's" : "cam0/sensor.yaml") {
  fs::path root = requireDir(root_dir);
  std::error_code ec;
  fs::path mav = fs::is_directory(root / "mav0", ec) ? root / "mav0" : root;
  if (!fs::is_directory(mav / "cam0", ec) && !fs::is_directory(mav / "imu0", ec)) {
    throw InputError(root_dir, 0, "", "not an EuRoC ASL sequence: expected mav0/ (or cam0/ and imu0/) inside");
  }
  mav_dir_ = mav.string();
  fs::path cam = requireDir(mav / "cam0");
  fs::path imu = requireDir(mav / "imu0");
  camera_ = calibration.camera ? *calibration.camera : readEurocCameraYaml(requireFile(cam / "sensor.yaml"));
  imu_noise_ = calibration.imu_noise ? *calibration.imu_noise
                                     : readEurocImuYaml(requireFile(imu / "sensor.yaml"));
  image_dir_ = requireDir(cam / "data").string();

  frame_csv_ = std::make_unique<CsvReader>(requireFile(cam / "data.csv"));
  frame_csv_->setColumnNames({"timestamp", "filename"});
  imu_csv_ = std::make_unique<CsvReader>(requireFile(imu / "data.csv"));
  imu_csv_->setColumnNames({"timestamp", "w_x", "w_y", "w_z", "a_x", "a_y", "a_z"});

  for (const char* gt_dir : {"state_groundtruth_estimate0", "mocap0"}) {
    const fs::path gt = mav / gt_dir / "data.csv";
    if (ground_truth_path_.empty() && fs::is_regular_file(gt, ec)) ground_truth_path_ = gt.string();
  }

  frame_pending_ = readFrameRow();
  if (!frame_pending_) throw InputError(frame_csv_->path(), 0, "", "no frames: the camera stream is empty");
  imu_pending_ = readImuRow();
  if (!imu_pending_) throw InputError(imu_csv_->path(), 0, "", "no IMU samples: the IMU stream is empty");
}

EurocReader::~EurocReader() = default;

SourceCounts EurocReader::counts() const {
  SourceCounts c;
  c.skipped_frames = skipped_frames_;
  return c;
}

std::string EurocReader::description() const { return "ASL folder " + mav_dir_; }
EurocReader::EurocReader(EurocReader&&) noexcept = default;
EurocReader& EurocReader::operator=(EurocReader&&) noexcept = default;

bool EurocReader::readFrameRow() {
  CsvReader& csv = *frame_csv_;
  if (!csv.next()) return false;
  csv.requireColumns(2);
  int64_t t = csv.int64At(0);
  requireIncreasing(csv, t, frame_t_ns_, frame_line_);
  if (csv.field(1).empty()) csv.fail(1, "empty file name");
  frame_t_ns_ = t;
  frame_file_ = csv.field(1);
  frame_line_ = csv.lineNumber();
  return true;
}

bool EurocReader::readImuRow() {
  CsvReader& csv = *imu_csv_;
  if (!csv.next()) return false;
  csv.requireColumns(7);
  int64_t t = csv.int64At(0);
  requireIncreasing(csv, t, imu_.t_ns, imu_line_);
  for (int i = 0; i < 3; ++i) {
    imu_.gyro[i] = csv.doubleAt(1 + i);
    imu_.accel[i] = csv.doubleAt(4 + i);
  }
  imu_.t_ns = t;
  imu_line_ = csv.lineNumber();
  return true;
}

bool EurocReader::loadFrame(Frame& f) {
  f.t_ns = frame_t_ns_ + image_time_shift_ns_;
  f.path = (fs::path(image_dir_) / frame_file_).string();
  f.image.release();
  std::string problem;
  std::error_code ec;
  if (!fs::is_regular_file(f.path, ec)) {
    problem = "image '" + f.path + "' is missing";
  } else if (options_.load_images) {
    try {
      f.image = readImageFile(f.path, ImageRead::kGrey);
    } catch (const InputError& e) {
      f.image.release();
      problem = std::string("image cannot be decoded: ") + e.what();
    }
  }
  if (!problem.empty()) {
    InputError error(frame_csv_->path(), frame_line_, "filename", problem);
    if (!options_.skip_bad_frames) throw error;
    ++skipped_frames_;
    std::cerr << "warning: " << error.what() << "; frame skipped\n";
    return false;
  }
  if (options_.load_images && (f.image.cols != camera_.width || f.image.rows != camera_.height)) {
    throw InputError(frame_csv_->path(), frame_line_, "filename",
                     "image '" + f.path + "' is " + std::to_string(f.image.cols) + "x" +
                         std::to_string(f.image.rows) + " but " + calibration_source_ + " resolution is " +
                         std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
  }
  return true;
}

// A bad row met while reading ahead is reported by the following next() call, so the measurement
// in hand is still delivered.
template <typename F>
bool EurocReader::readAhead(F&& read) {
  try {
    return read();
  } catch (const InputError& e) {
    error_ = e;
    return false;
  }
}

bool EurocReader::next(Measurement& m) {
  if (error_) throw *error_;
  try {
    return nextMeasurement(m);
  } catch (const InputError& e) {
    error_ = e;  // sticky: the streams are in an undefined position now
    throw;
  }
}

bool EurocReader::nextMeasurement(Measurement& m) {
  while (true) {
    if (error_) throw *error_;  // a read-ahead failed (e.g. after a skipped frame)
    if (!frame_pending_ && !imu_pending_) break;
    if (imu_pending_ && (!frame_pending_ || imu_.t_ns <= frame_t_ns_ + image_time_shift_ns_)) {
      m.type = Measurement::Type::kImu;
      m.imu = imu_;
      m.frame = Frame();
      imu_pending_ = readAhead([this] { return readImuRow(); });
      return true;
    }
    Frame f;
    bool ok = loadFrame(f);
    frame_pending_ = readAhead([this] { return readFrameRow(); });
    if (ok) {
      m.type = Measurement::Type::kFrame;
      m.frame = std::move(f);
      ++frames_returned_;
      return true;
    }
  }
  if (frames_returned_ == 0) {
    throw InputError(frame_csv_->path(), 0, "",
                     "no usable frames: all " + std::to_string(skipped_frames_) + " were skipped");
  }
  return false;
}

}  // namespace adugs::data

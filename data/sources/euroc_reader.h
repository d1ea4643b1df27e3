#pragma once
// Streaming reader for EuRoC ASL sequences:
//   root/mav0/cam0/data.csv (#timestamp [ns],filename), cam0/data/*.png, cam0/sensor.yaml
//   root/mav0/imu0/data.csv (#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z), imu0/sensor.yaml
//   root/mav0/state_groundtruth_estimate0/data.csv, or mav0/mocap0/data.csv as TUM-VI has it
//   (optional; only its path is reported)
// TUM-VI folders have this layout too; their 16-bit PNGs (the `_16` sets) are read as 8-bit grey
// (the upper 8 bits), which is what the front-end uses.
// `root` may also be the mav0 folder itself.
//
// Streaming: only one pending row of each CSV is held; next() returns the earlier of the two
// (IMU first on equal timestamps), loading the frame's image only when it is returned.
//
// Bad input is an InputError naming file, line and field: missing folders/files, malformed CSV
// rows (column count, non-numeric, non-finite IMU values), timestamps that do not strictly
// increase within a CSV, an image that is missing, unreadable or not of the sensor.yaml size, and
// an empty sequence (no frame or no IMU row). Errors in later rows surface from next(): every
// measurement up to the bad row is delivered, then next() throws, and keeps throwing that error.
//
// skip_bad_frames: a MISSING or UNREADABLE (corrupt) image is skipped with a warning on stderr and
// counted in skippedFrames(), because real EuRoC-format recordings do drop frames and one lost
// image should not end a run. Everything else stays fatal even then: IMU rows and timestamps feed
// the estimator directly (skipping them would silently corrupt preintegration), and a wrong image
// size means the calibration does not belong to the images. If every frame is skipped, next()
// throws at the end of the sequence.
// load_images = false: frames carry only t_ns and path; the image file must still exist
// (or is skipped as above), but it is not decoded, so corrupt/size problems go unnoticed.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/input_error.h"
#include "data/sources/sequence_source.h"
#include "data/types.h"

namespace adugs::data {

class CsvReader;

struct EurocReaderOptions {
  bool skip_bad_frames = false;
  bool load_images = true;
};

// Calibration given by the caller (e.g. from Kalibr files): the corresponding sensor.yaml is then
// not needed (TUM-VI folders and many user recordings have none) and not read. Kalibr's
// timeshift_cam_imu is applied to the image timestamps (t_imu = t_cam + shift).
struct EurocCalibrationOverride {
  std::optional<CameraCalibration> camera;
  std::optional<ImuNoise> imu_noise;
  int64_t image_time_shift_ns = 0;
};

class EurocReader : public SequenceSource {
 public:
  // Opens the sequence, reads both sensor.yaml files and the first row of each CSV.
  explicit EurocReader(const std::string& root_dir, EurocReaderOptions options = {},
                       EurocCalibrationOverride calibration = {});
  ~EurocReader() override;
  EurocReader(EurocReader&&) noexcept;
  EurocReader& operator=(EurocReader&&) noexcept;

  // The next measurement in timestamp order; false at the end of both streams.
  bool next(Measurement& m) override;
  SourceCounts counts() const override;
  std::string description() const override;

  const CameraCalibration& camera() const { return camera_; }
  const ImuNoise& imuNoise() const { return imu_noise_; }
  bool hasGroundTruth() const { return !ground_truth_path_.empty(); }
  const std::string& groundTruthPath() const { return ground_truth_path_; }  // "" if none
  const std::string& mavDir() const { return mav_dir_; }
  size_t skippedFrames() const { return skipped_frames_; }

 private:
  bool readFrameRow();  // false at end of cam0/data.csv
  bool readImuRow();    // false at end of imu0/data.csv
  bool loadFrame(Frame& f);  // false if the frame was skipped
  bool nextMeasurement(Measurement& m);
  template <typename F>
  bool readAhead(F&& read);

  EurocReaderOptions options_;
  int64_t image_time_shift_ns_ = 0;
  std::string calibration_source_;  // names the calibration in image-size errors
  std::string mav_dir_, image_dir_, ground_truth_path_;
  CameraCalibration camera_;
  ImuNoise imu_noise_;
  std::unique_ptr<CsvReader> frame_csv_, imu_csv_;
  bool frame_pending_ = false, imu_pending_ = false;
  int64_t frame_t_ns_ = 0;
  std::string frame_file_;
  long frame_line_ = 0;  // line of the pending frame row (0: none read yet)
  ImuSample imu_;
  long imu_line_ = 0;
  size_t frames_returned_ = 0, skipped_frames_ = 0;
  std::optional<InputError> error_;
};

}  // namespace adugs::data

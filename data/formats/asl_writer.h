#pragma once
// Writes an EuRoC ASL sequence folder as the measurements come (the simulator's sequences,
// `adugs record`), readable by EurocReader, `adugs run` and `adugs calib`:
//   root/mav0/cam0/data/<t_ns>.png, cam0/data.csv, cam0/sensor.yaml   images (8-bit grey or BGR)
//   root/mav0/imu0/data.csv, imu0/sensor.yaml                         IMU, EuRoC columns (with an IMU)
//   root/mav0/mask0/data/<t_ns>.png, mask0/data.csv                   dynamic masks (when asked for)
//   root/mav0/state_groundtruth_estimate0/data.csv                    ground truth (writeGroundTruth)
// Images are written under a temporary name and renamed; each camera CSV row is flushed after its
// image, IMU rows with every frame and at flush(), so a killed writer leaves a consistent, shorter
// sequence. Numbers are written in their shortest exact form.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/formats/euroc_sensor_yaml.h"
#include "data/types.h"

namespace adugs::data {

// What an ASL folder holds after writing (root/mav0/...): rows of cam0/data.csv, PNG files in
// cam0/data/, rows of imu0/data.csv (0 for a file or folder that does not exist), so that a
// recorder can check that nothing it acquired was lost on the way to the disk.
struct AslFolderCounts {
  size_t camera_rows = 0, image_files = 0, imu_rows = 0;
};
AslFolderCounts countAslFolder(const std::string& root);

class AslWriter {
 public:
  // Creates the folders under root (root/mav0/...) and the sensor.yaml files (imu0 only when
  // `imu` is given; camera_comment: the camera file's comment, e.g. where its calibration came
  // from). Throws InputError naming the folder or file that cannot be created.
  // camera_first_comment: "# ..." lines at the top of cam0/sensor.yaml (a calibration verdict).
  AslWriter(const std::string& root, const CameraCalibration& camera, const ImuNoise* imu, bool masks,
            const std::string& camera_comment = "written by adugs", const std::string& camera_first_comment = "");

  // One image (and its mask when the writer has masks); frames in increasing time.
  void writeFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& mask = cv::Mat());
  // One IMU row (needs an IMU); samples in increasing time.
  void writeImu(const ImuSample& sample);
  // The whole ground-truth file, written atomically.
  void writeGroundTruth(const std::vector<GroundTruthState>& states);
  // Flushes the IMU rows; InputError when a write failed.
  void flush();

  int framesWritten() const { return frames_; }
  size_t imuWritten() const { return imu_rows_; }
  const std::string& mavDir() const { return mav_; }

 private:
  std::string mav_;
  std::ofstream cam_csv_, mask_csv_, imu_csv_;
  bool masks_;
  int frames_ = 0;
  size_t imu_rows_ = 0;
  int64_t last_frame_t_ = -1, last_imu_t_ = -1;
};

// Shortest text of a double that reads back to the same value.
std::string exactNumber(double v);

}  // namespace adugs::data

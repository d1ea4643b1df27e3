#pragma once
// A recorded (or live) visual-inertial sequence as one time-ordered stream of measurements:
// IMU samples and camera frames, streamed (nothing holds the whole sequence). `adugs run`
// consumes this interface; each format is one implementation (EuRoC/TUM-VI folders, ROS1 bags).
//
// Contract of next(): measurements come in non-decreasing time, IMU first on equal timestamps;
// frames carry a CV_8UC1 image unless the source was opened without image decoding. Bad input is
// an InputError naming the file and field.
//
// Live sources (a camera, a video played as a camera, a sensor-paced replay) say so with isLive():
// their measurements arrive at sensor pace whether or not anyone reads them, next() blocks until
// the next one and returns false when the device stops (or after stop()). The pipeline then reads
// them on a thread of their own and drops frames (never IMU samples) when it falls behind.
// counts() and description() are called from the thread that calls next(), or after it ended.
#include <cstddef>
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "data/types.h"

namespace adugs::data {

struct Frame {
  int64_t t_ns = 0;
  std::string path;  // the image file, or "" when the image came from a bag message
  cv::Mat image;     // CV_8UC1; empty when images are not decoded
  cv::Mat colour;    // CV_8UC3 BGR when the source has colour (detectors and views use it); else empty
};

struct Measurement {
  enum class Type { kImu, kFrame };
  Type type = Type::kImu;
  ImuSample imu;  // valid when type == kImu
  Frame frame;    // valid when type == kFrame
  bool isImu() const { return type == Type::kImu; }
  bool isFrame() const { return type == Type::kFrame; }
  int64_t timeNs() const { return isImu() ? imu.t_ns : frame.t_ns; }
};

// What a source left out, reported in the run summary.
struct SourceCounts {
  size_t skipped_frames = 0;   // missing / corrupt images skipped on request
  size_t late_dropped = 0;     // messages whose stamp came after the reorder window had passed it
  size_t imu_dropped = 0;      // IMU samples with a stamp equal to or before the previous one
  size_t unmatched_gyro = 0;   // split IMU: gyro samples outside the accelerometer's time span
  size_t frames_lost = 0;      // live sources: frames the sensor took that never arrived whole
};

class SequenceSource {
 public:
  virtual ~SequenceSource() = default;
  // The next measurement in time order; false at the end of the sequence.
  virtual bool next(Measurement& m) = 0;
  virtual SourceCounts counts() const = 0;
  // One line for logs and the run summary, e.g. "ROS bag /x.bag (/cam0/image_raw, /imu0)".
  virtual std::string description() const = 0;
  // True for live sources (see above); recorded sequences are read as fast as they are consumed.
  virtual bool isLive() const { return false; }
  // Asks next() to return false soon, also when it is blocked in another thread; safe to call from
  // any thread, more than once. Sources whose next() never waits long need not override it.
  virtual void stop() {}
  // Why next() returned false when that was not the end of a recording: after stop(), or when a
  // device went away or stalled, e.g. "/dev/video2: VIDIOC_DQBUF: No such device (camera
  // unplugged?)"; "" otherwise. The pipeline writes it as the run's end_detail.
  virtual std::string stopReason() const { return {}; }
};

}  // namespace adugs::data

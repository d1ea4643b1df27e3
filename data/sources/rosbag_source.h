#pragma once
// ROS1 bag playback without ROS (Debian's rosbag_storage): camera images and IMU samples of a
// bag as a SequenceSource.
//
// Topics: one image topic (sensor_msgs/Image or sensor_msgs/CompressedImage) and either one
// sensor_msgs/Imu topic, or an accelerometer and a gyroscope topic (both sensor_msgs/Imu, using
// linear_acceleration and angular_velocity respectively), united on the gyro stamps (ImuUnifier).
//
// Order: by header.stamp, not by the bag's record time: messages pass a StampReorderBuffer of
// `reorder_window_ns`; one that arrives after the window has passed its stamp is dropped and
// counted (late_dropped). IMU samples whose stamp does not increase are dropped and counted
// (imu_dropped); a non-finite IMU value is an error.
//
// Bad input is an InputError naming the bag: a file that is not a readable bag (truncated,
// corrupt, empty), a topic that is not in the bag (the message lists the bag's topics and types),
// a topic of the wrong type, no messages on a topic, an unsupported encoding, an image of another
// size than the calibration.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "data/sources/rosbag_topics.h"
#include "data/sources/sequence_source.h"

namespace rosbag {
class Bag;
class View;
}  // namespace rosbag

namespace adugs::data {

struct RosbagTopics {
  std::string image;
  std::string imu;    // one topic with both sensors, or
  std::string accel;  // two topics (then imu is empty)
  std::string gyro;
};

struct RosbagSourceOptions {
  RosbagTopics topics;
  int64_t reorder_window_ns = 100'000'000;  // 0.1 s: recorders delay images by tens of ms
  bool load_images = true;
  int expected_width = 0, expected_height = 0;  // the calibration's image size; 0 = unchecked
  int64_t image_time_shift_ns = 0;  // added to image stamps (Kalibr timeshift_cam_imu)
};

class RosbagSource : public SequenceSource {
 public:
  RosbagSource(const std::string& bag_path, RosbagSourceOptions options);
  ~RosbagSource() override;

  bool next(Measurement& m) override;
  SourceCounts counts() const override;
  std::string description() const override;
  // The bag's topics (name -> type), as read when it was opened.
  const std::map<std::string, BagTopic>& topics() const { return topics_; }
  // The image topic's rate from its record times (messages - 1) / span; 0 with one message.
  double imageRateHz() const { return image_rate_hz_; }

 private:
  struct Pending;
  void readOne();
  bool release(bool flush);

  std::string path_;
  RosbagSourceOptions options_;
  std::unique_ptr<rosbag::Bag> bag_;
  std::map<std::string, BagTopic> topics_;
  double image_rate_hz_ = 0;
  std::unique_ptr<rosbag::View> view_;
  struct Cursor;
  std::unique_ptr<Cursor> cursor_;
  std::unique_ptr<Pending> pending_;
  SourceCounts counts_;
  size_t frames_returned_ = 0, imu_returned_ = 0;
  bool input_done_ = false;
};

}  // namespace adugs::data

#include "data/sources/rosbag_source.h"

#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "data/input_error.h"
#include "data/sources/imu_unifier.h"
#include "data/sources/ros_image.h"
#include "data/sources/rosbag_topics.h"
#include "data/sources/stamp_reorder_buffer.h"

namespace adugs::data {
namespace {

enum class Kind { kImu, kAccel, kGyro, kImage };
constexpr int kRankImu = 0, kRankImage = 1;  // IMU first on equal stamps

// One bag message on its way through the reorder buffer; images are decoded on release, so a
// late (dropped) image costs no decoding.
struct Raw {
  Kind kind = Kind::kImu;
  Eigen::Vector3d accel = Eigen::Vector3d::Zero(), gyro = Eigen::Vector3d::Zero();
  sensor_msgs::Image::ConstPtr image;
  sensor_msgs::CompressedImage::ConstPtr compressed;
};

Eigen::Vector3d toVector(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

}  // namespace

struct RosbagSource::Cursor {
  rosbag::View::iterator it, end;
};

struct RosbagSource::Pending {
  explicit Pending(int64_t window_ns) : reorder(window_ns) {}
  StampReorderBuffer<Raw> reorder;
  ImuUnifier unifier;
  std::deque<Measurement> ready;    // released, in time order
  std::deque<Frame> waiting_frames;  // split IMU: frames until the accelerometer passes them
  int64_t last_imu_t = 0, last_accel_t = 0;
  bool any_imu = false, any_accel = false;
};

RosbagSource::RosbagSource(const std::string& bag_path, RosbagSourceOptions options)
    : path_(bag_path), options_(std::move(options)) {
  const RosbagTopics& t = options_.topics;
  if (t.image.empty()) throw InputError(path_, 0, "image_topic", "no image topic given");
  const bool split = t.imu.empty();
  if (split && (t.accel.empty() || t.gyro.empty()))
    throw InputError(path_, 0, "imu_topic",
                     "give one IMU topic, or both an accelerometer and a gyroscope topic");

  bag_ = openBag(path_);
  topics_ = listBagTopics(*bag_);
  requireTopic(path_, topics_, "image_topic", t.image, {"sensor_msgs/Image", "sensor_msgs/CompressedImage"});
  std::vector<std::string> names{t.image};
  const std::vector<std::pair<std::string, std::string>> imu_topics =
      split ? std::vector<std::pair<std::string, std::string>>{{"accel_topic", t.accel}, {"gyro_topic", t.gyro}}
            : std::vector<std::pair<std::string, std::string>>{{"imu_topic", t.imu}};
  for (const auto& [key, name] : imu_topics) {
    requireTopic(path_, topics_, key, name, {"sensor_msgs/Imu"});
    names.push_back(name);
  }
  try {
    for (const std::string& name : names)
      if (rosbag::View(*bag_, rosbag::TopicQuery(name)).size() == 0)
        throw InputError(path_, 0, "topic " + name, "the topic has no messages in this bag");
    rosbag::View images(*bag_, rosbag::TopicQuery(t.image));  // its getters are not const
    const double span = (images.getEndTime() - images.getBeginTime()).toSec();
    if (images.size() > 1 && span > 0) image_rate_hz_ = static_cast<double>(images.size() - 1) / span;
    view_ = std::make_unique<rosbag::View>(*bag_, rosbag::TopicQuery(names));
    cursor_ = std::make_unique<Cursor>(Cursor{view_->begin(), view_->end()});
  } catch (const rosbag::BagException& e) {
    throw InputError(path_, 0, "", std::string("corrupt ROS bag: ") + e.what());
  }
  pending_ = std::make_unique<Pending>(options_.reorder_window_ns);
}

RosbagSource::~RosbagSource() = default;

SourceCounts RosbagSource::counts() const {
  SourceCounts c = counts_;
  c.unmatched_gyro = pending_->unifier.unmatched();
  return c;
}

std::string RosbagSource::description() const {
  const RosbagTopics& t = options_.topics;
  return "ROS bag " + path_ + " (images " + t.image + ", IMU " +
         (t.imu.empty() ? t.accel + " + " + t.gyro : t.imu) + ")";
}

bool RosbagSource::next(Measurement& m) {
  Pending& p = *pending_;
  while (true) {
    if (!p.ready.empty()) {
      m = std::move(p.ready.front());
      p.ready.pop_front();
      if (m.isFrame()) ++frames_returned_;
      else ++imu_returned_;
      return true;
    }
    if (release(input_done_)) continue;
    if (!input_done_) {
      readOne();
      continue;
    }
    if (!p.waiting_frames.empty() || p.unifier.pendingGyro() > 0) {  // end: nothing more to match
      p.unifier.finish();
      for (Frame& f : p.waiting_frames) {
        Measurement out;
        out.type = Measurement::Type::kFrame;
        out.frame = std::move(f);
        p.ready.push_back(std::move(out));
      }
      p.waiting_frames.clear();
      continue;
    }
    if (frames_returned_ == 0) throw InputError(path_, 0, "topic " + options_.topics.image, "no image was played back");
    if (imu_returned_ == 0) throw InputError(path_, 0, "imu_topic", "no IMU sample was played back");
    return false;
  }
}

void RosbagSource::readOne() {
  Cursor& c = *cursor_;
  try {
    if (c.it == c.end) {
      input_done_ = true;
      return;
    }
    const rosbag::MessageInstance& msg = *c.it;
    const std::string& topic = msg.getTopic();
    const RosbagTopics& t = options_.topics;
    Raw raw;
    int64_t stamp = 0;
    int rank = kRankImu;
    if (topic == t.image) {
      raw.kind = Kind::kImage;
      rank = kRankImage;
      if (msg.getDataType() == "sensor_msgs/CompressedImage") {
        raw.compressed = msg.instantiate<sensor_msgs::CompressedImage>();
        if (!raw.compressed) throw InputError(path_, 0, "topic " + topic, "message does not decode as " + msg.getDataType());
        stamp = static_cast<int64_t>(raw.compressed->header.stamp.toNSec());
      } else {
        raw.image = msg.instantiate<sensor_msgs::Image>();
        if (!raw.image) throw InputError(path_, 0, "topic " + topic, "message does not decode as " + msg.getDataType());
        stamp = static_cast<int64_t>(raw.image->header.stamp.toNSec());
      }
      stamp += options_.image_time_shift_ns;
    } else {
      const auto imu = msg.instantiate<sensor_msgs::Imu>();
      if (!imu) throw InputError(path_, 0, "topic " + topic, "message does not decode as sensor_msgs/Imu");
      stamp = static_cast<int64_t>(imu->header.stamp.toNSec());
      raw.accel = toVector(imu->linear_acceleration);
      raw.gyro = toVector(imu->angular_velocity);
      raw.kind = topic == t.imu ? Kind::kImu : topic == t.accel ? Kind::kAccel : Kind::kGyro;
      const Eigen::Vector3d& used = raw.kind == Kind::kAccel ? raw.accel : raw.gyro;
      const bool finite = used.allFinite() && (raw.kind != Kind::kImu || raw.accel.allFinite());
      if (!finite)
        throw InputError(path_, 0, "topic " + topic,
                         "non-finite IMU value at stamp " + std::to_string(stamp) + " ns");
    }
    ++c.it;
    if (!pending_->reorder.push(stamp, rank, std::move(raw))) ++counts_.late_dropped;
  } catch (const rosbag::BagException& e) {
    throw InputError(path_, 0, "", std::string("corrupt ROS bag: ") + e.what());
  } catch (const ros::Exception& e) {
    throw InputError(path_, 0, "", std::string("corrupt ROS bag message: ") + e.what());
  }
}

// Moves one message from the reorder buffer to `ready` (through the IMU unifier when split).
bool RosbagSource::release(bool flush) {
  Pending& p = *pending_;
  Raw raw;
  int64_t stamp = 0;
  if (!p.reorder.pop(&raw, &stamp, flush)) return false;

  auto pushImu = [&](const ImuSample& s) {
    if (p.any_imu && s.t_ns <= p.last_imu_t) {
      ++counts_.imu_dropped;
      return;
    }
    p.any_imu = true;
    p.last_imu_t = s.t_ns;
    Measurement out;
    out.type = Measurement::Type::kImu;
    out.imu = s;
    p.ready.push_back(std::move(out));
  };
  auto pushFrame = [&](Frame f) {
    Measurement out;
    out.type = Measurement::Type::kFrame;
    out.frame = std::move(f);
    p.ready.push_back(std::move(out));
  };

  switch (raw.kind) {
    case Kind::kImu: {
      ImuSample s;
      s.t_ns = stamp;
      s.accel = raw.accel;
      s.gyro = raw.gyro;
      pushImu(s);
      break;
    }
    case Kind::kImage: {
      Frame f;
      f.t_ns = stamp;
      if (options_.load_images) {
        const std::string& topic = options_.topics.image;
        f.image = raw.compressed ? decodeRosImage(*raw.compressed, path_, topic)
                                 : decodeRosImage(*raw.image, path_, topic);
        if (options_.expected_width > 0 &&
            (f.image.cols != options_.expected_width || f.image.rows != options_.expected_height))
          throw InputError(path_, 0, "topic " + topic,
                           "image is " + std::to_string(f.image.cols) + "x" + std::to_string(f.image.rows) +
                               " but the camera calibration's resolution is " +
                               std::to_string(options_.expected_width) + "x" +
                               std::to_string(options_.expected_height));
      }
      if (options_.topics.imu.empty()) p.waiting_frames.push_back(std::move(f));
      else pushFrame(std::move(f));
      break;
    }
    case Kind::kAccel:
    case Kind::kGyro: {
      if (raw.kind == Kind::kAccel) {
        p.unifier.addAccel(stamp, raw.accel);
        p.last_accel_t = stamp;
        p.any_accel = true;
      } else {
        p.unifier.addGyro(stamp, raw.gyro);
      }
      // United samples and the frames they pass, merged in time order.
      ImuSample s;
      while (p.unifier.pop(&s)) {
        while (!p.waiting_frames.empty() && p.waiting_frames.front().t_ns < s.t_ns) {
          pushFrame(std::move(p.waiting_frames.front()));
          p.waiting_frames.pop_front();
        }
        pushImu(s);
      }
      // Every gyro stamp up to the newest accelerometer sample is resolved (the input is in stamp
      // order), so frames up to it have all their IMU samples before them.
      while (p.any_accel && !p.waiting_frames.empty() && p.waiting_frames.front().t_ns <= p.last_accel_t) {
        pushFrame(std::move(p.waiting_frames.front()));
        p.waiting_frames.pop_front();
      }
      break;
    }
  }
  return true;
}

}  // namespace adugs::data

#pragma once
// Opening a ROS1 bag and checking its topics, shared by playback, ground truth and `adugs bag info`.
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rosbag {
class Bag;
}

namespace adugs::data {

struct BagTopic {
  std::string type;  // e.g. "sensor_msgs/Imu"
  std::string md5;
};

// Opens for reading; a missing, empty, truncated or corrupt file is an InputError naming it.
std::unique_ptr<rosbag::Bag> openBag(const std::string& path);

// Topic name -> type, from the bag's connection records.
std::map<std::string, BagTopic> listBagTopics(const rosbag::Bag& bag);

// "/a (sensor_msgs/Image), /b (sensor_msgs/Imu)": for error messages.
std::string describeTopics(const std::map<std::string, BagTopic>& topics);

// The topic must exist and be of one of `types`; otherwise an InputError naming the bag, the
// option (`field`, e.g. "image_topic") and listing the bag's topics.
void requireTopic(const std::string& bag_path, const std::map<std::string, BagTopic>& topics,
                  const std::string& field, const std::string& topic, const std::vector<std::string>& types);

}  // namespace adugs::data

#include "data/sources/rosbag_topics.h"

#include <filesystem>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

#include "data/input_error.h"

namespace adugs::data {

std::unique_ptr<rosbag::Bag> openBag(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path, 0, "", fs::exists(path, ec) ? "is not a regular file" : "file not found");
  if (fs::file_size(path, ec) == 0) throw InputError(path, 0, "", "empty file (0 bytes), not a ROS bag");
  auto bag = std::make_unique<rosbag::Bag>();
  try {
    bag->open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw InputError(path, 0, "", std::string("not a readable ROS1 bag (truncated or corrupt? a recording cut short has no index; `rosbag reindex` repairs it): ") + e.what());
  }
  return bag;
}

std::map<std::string, BagTopic> listBagTopics(const rosbag::Bag& bag) {
  std::map<std::string, BagTopic> topics;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics[c->topic] = {c->datatype, c->md5sum};
  return topics;
}

std::string describeTopics(const std::map<std::string, BagTopic>& topics) {
  if (topics.empty()) return "(the bag has no topics)";
  std::string s;
  for (const auto& [name, t] : topics) s += (s.empty() ? "" : ", ") + name + " (" + t.type + ")";
  return s;
}

void requireTopic(const std::string& bag_path, const std::map<std::string, BagTopic>& topics,
                  const std::string& field, const std::string& topic, const std::vector<std::string>& types) {
  std::string wanted;
  for (const std::string& t : types) wanted += (wanted.empty() ? "" : " or ") + t;
  const auto it = topics.find(topic);
  if (it == topics.end())
    throw InputError(bag_path, 0, field,
                     "topic '" + topic + "' is not in the bag; its topics: " + describeTopics(topics));
  for (const std::string& t : types)
    if (it->second.type == t) return;
  throw InputError(bag_path, 0, field,
                   "topic '" + topic + "' has type " + it->second.type + ", expected " + wanted);
}

}  // namespace adugs::data

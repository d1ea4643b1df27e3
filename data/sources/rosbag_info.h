#pragma once
// What `adugs bag info BAG` prints, as `rosbag info` does: version, time span, size, message
// count, chunk compression, and per topic its type, message count and mean rate, so users find
// the topic names to pass to `adugs run`.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace adugs::data {

struct BagTopicInfo {
  std::string name, type, md5;
  uint64_t messages = 0;
  double rate_hz = 0;  // (messages - 1) / span between the first and last record time
};

struct BagInfo {
  std::string path;
  std::string version;  // "2.0"
  uint64_t size_bytes = 0;
  double start_s = 0, end_s = 0;  // record time
  uint64_t messages = 0;
  std::map<std::string, uint64_t> chunks_by_compression;  // "none" / "bz2" / "lz4" -> count
  std::vector<BagTopicInfo> topics;
};

// Throws InputError naming the file for anything that is not a readable ROS1 bag.
BagInfo readBagInfo(const std::string& path);
std::string formatBagInfo(const BagInfo& info);

}  // namespace adugs::data

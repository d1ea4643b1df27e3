#include "data/sources/rosbag_info.h"

#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

#include "data/input_error.h"
#include "data/sources/rosbag_topics.h"

namespace adugs::data {
namespace {

// The compression of every chunk record (op 0x05). rosbag_storage reads chunk compression but
// does not expose it, so the record headers are scanned: after the "#ROSBAG V2.0\n" line every
// record is <uint32 header length><header: <uint32 len><name=value>...><uint32 data length><data>.
std::map<std::string, uint64_t> scanChunkCompression(const std::string& path) {
  std::map<std::string, uint64_t> chunks;
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  std::getline(in, magic);
  auto readU32 = [&](uint32_t* v) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
    *v = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<uint32_t>(b[3]) << 24);
    return true;
  };
  uint32_t header_len = 0, data_len = 0;
  while (readU32(&header_len)) {
    std::string header(header_len, '\0');
    if (header_len > (1u << 24) || !in.read(header.data(), header_len) || !readU32(&data_len)) break;
    std::string op, compression;
    for (size_t i = 0; i + 4 <= header.size();) {
      uint32_t len = 0;
      std::memcpy(&len, header.data() + i, 4);  // little-endian, as the bag format and x86
      i += 4;
      if (len > header.size() - i) break;
      const std::string field = header.substr(i, len);
      i += len;
      const size_t eq = field.find('=');
      if (eq == std::string::npos) continue;
      const std::string name = field.substr(0, eq);
      if (name == "op") op = field.substr(eq + 1);
      if (name == "compression") compression = field.substr(eq + 1);
    }
    if (op.size() == 1 && op[0] == 0x05) ++chunks[compression.empty() ? "?" : compression];
    in.seekg(data_len, std::ios::cur);
  }
  return chunks;
}

}  // namespace

BagInfo readBagInfo(const std::string& path) {
  const auto bag = openBag(path);
  BagInfo info;
  info.path = path;
  info.version = std::to_string(bag->getMajorVersion()) + "." + std::to_string(bag->getMinorVersion());
  info.size_bytes = bag->getSize();
  try {
    rosbag::View all(*bag);
    info.messages = all.size();
    if (info.messages > 0) {
      info.start_s = all.getBeginTime().toSec();
      info.end_s = all.getEndTime().toSec();
    }
    for (const auto& [name, topic] : listBagTopics(*bag)) {
      rosbag::View v(*bag, rosbag::TopicQuery(name));
      BagTopicInfo t{name, topic.type, topic.md5, v.size(), 0.0};
      const double span = t.messages > 1 ? (v.getEndTime() - v.getBeginTime()).toSec() : 0.0;
      if (span > 0) t.rate_hz = static_cast<double>(t.messages - 1) / span;
      info.topics.push_back(t);
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(path, 0, "", std::string("corrupt ROS bag: ") + e.what());
  }
  info.chunks_by_compression = scanChunkCompression(path);
  return info;
}

std::string formatBagInfo(const BagInfo& info) {
  std::ostringstream o;
  o << std::fixed;
  o << "path:        " << info.path << "\n"
    << "version:     " << info.version << "\n"
    << std::setprecision(3) << "duration:    " << (info.end_s - info.start_s) << " s\n"
    << std::setprecision(6) << "start:       " << info.start_s << "\n"
    << "end:         " << info.end_s << "\n"
    << "size:        " << info.size_bytes << " bytes\n"
    << "messages:    " << info.messages << "\n"
    << "compression: ";
  if (info.chunks_by_compression.empty()) o << "(no chunks)";
  bool first = true;
  for (const auto& [kind, n] : info.chunks_by_compression) {
    o << (first ? "" : ", ") << kind << " [" << n << " chunk" << (n == 1 ? "" : "s") << "]";
    first = false;
  }
  o << "\n";
  o << "types:\n";
  std::map<std::string, std::string> types;
  for (const BagTopicInfo& t : info.topics) types[t.type] = t.md5;
  for (const auto& [type, md5] : types) o << "  " << type << " [" << md5 << "]\n";
  o << "topics:\n";
  for (const BagTopicInfo& t : info.topics) {
    o << "  " << std::left << std::setw(32) << t.name << std::right << std::setw(8) << t.messages
      << " msgs  " << std::setprecision(1) << std::setw(8) << t.rate_hz << " Hz  " << t.type << "\n";
  }
  return o.str();
}

}  // namespace adugs::data

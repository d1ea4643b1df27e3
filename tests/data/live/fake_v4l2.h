#pragma once
// A fake of the kernel's V4L2 + uvcvideo ioctl layer behind data::V4l2Io, for tests of the live
// capture code without a camera: video and metadata capture nodes with formats, sizes and rates,
// format and rate negotiation, memory-mapped streaming buffers with the driver's semantics
// (queued / filled queues, a frame counter that advances also when no buffer was free, buffer
// timestamps), the D4xx UVC extension unit and standard controls, and unplugging (-ENODEV). Each
// open node has a real eventfd as its file descriptor, readable while a filled buffer waits, so
// the code under test polls it as it polls a real node. Thread-safe: a device-simulator thread
// delivers frames while the code under test streams.
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "data/device/v4l2_io.h"

namespace adugs::test {

struct FakeFrameSize {
  int width, height;
  std::vector<double> rates_hz;
};
struct FakeFormat {
  uint32_t fourcc;
  std::string description;
  std::vector<FakeFrameSize> sizes;
};

class FakeV4l2 : public data::V4l2Io {
 public:
  ~FakeV4l2() override;
  // A video capture node (meta = false) or a metadata node listing `meta_formats`.
  void addVideoNode(const std::string& path, const std::vector<FakeFormat>& formats, const std::string& card = "Intel(R) RealSense(TM) Depth Ca");
  void addMetaNode(const std::string& path, const std::vector<uint32_t>& meta_formats);

  // Kernel side. Fills the oldest queued buffer of `path` with `bytes` (stamped `timestamp_ns`,
  // CLOCK_MONOTONIC, flagged erroneous if `error`) and wakes pollers; the node's frame counter
  // advances either way. False when the node is not streaming or had no queued buffer (the frame
  // is lost, as in the driver).
  bool deliver(const std::string& path, const std::vector<uint8_t>& bytes, int64_t timestamp_ns, bool error = false);
  // The camera goes away: every later ioctl on the node fails with ENODEV, pollers wake.
  void unplug(const std::string& path);

  // What the code under test did, for assertions.
  struct State {
    bool streaming = false;
    int open_count = 0;
    uint32_t fourcc = 0;
    int width = 0, height = 0;
    double fps = 0;
    uint32_t meta_format = 0;
    size_t buffers = 0;
    uint32_t sequence = 0;  // frames delivered or lost so far
    std::map<uint8_t, std::vector<uint8_t>> xu;  // extension unit 3: selector -> value
    std::map<uint32_t, int> controls;            // V4L2_CID_* -> value
    std::vector<std::string> calls;              // ioctl names in order
  };
  State state(const std::string& path);

  // data::V4l2Io
  int open(const std::string& path) override;
  void close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(int fd, size_t length, int64_t offset) override;
  void munmap(void* address, size_t length) override;

 private:
  struct Buffer {
    std::vector<uint8_t> data;
    uint32_t bytesused = 0, sequence = 0, flags = 0;
    int64_t timestamp_ns = 0;
  };
  struct Node {
    bool meta = false;
    std::string card;
    std::vector<FakeFormat> formats;
    std::vector<uint32_t> meta_formats;
    bool gone = false;
    int fd = -1;  // eventfd while open
    State state;
    std::vector<Buffer> buffers;
    std::deque<uint32_t> queued, done;
  };
  Node* nodeOfFd(int fd);
  int handle(Node& n, unsigned long request, void* arg);

  std::mutex mutex_;
  std::map<std::string, Node> nodes_;
};

}  // namespace adugs::test

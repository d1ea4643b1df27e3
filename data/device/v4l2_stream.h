#pragma once
// One V4L2 capture node (/dev/videoN) through V4l2Io: what it can do (capabilities, formats,
// frame sizes and rates), format and rate negotiation, and memory-mapped streaming
// (REQBUFS, QUERYBUF + mmap, QBUF, STREAMON, DQBUF, QBUF again, STREAMOFF). Works for video
// capture nodes and for UVC metadata nodes (V4L2_BUF_TYPE_META_CAPTURE).
//
// Errors: a node that cannot be opened or does not offer what is asked is an InputError naming
// the node (exit code 2: the user's camera, permissions or options); a failure while streaming
// ends the stream (gone()) with a message instead of throwing: a camera unplugged mid-run is a
// clean stop for the caller, not a crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "data/device/v4l2_io.h"

namespace adugs::data {

struct V4l2FrameSize {
  int width = 0, height = 0;
  std::vector<double> rates_hz;  // discrete frame intervals as rates; empty if none are listed
};

struct V4l2FormatInfo {
  uint32_t fourcc = 0;
  std::string description;
  std::vector<V4l2FrameSize> sizes;  // video nodes only
};

struct V4l2Buffer {
  uint32_t index = 0;
  const uint8_t* data = nullptr;
  size_t bytes = 0;           // bytesused
  uint32_t sequence = 0;      // the driver's frame counter: gaps are frames it dropped
  int64_t timestamp_ns = 0;   // the driver's stamp (CLOCK_MONOTONIC for uvcvideo)
  bool monotonic = false;     // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC
  bool error = false;         // V4L2_BUF_FLAG_ERROR: the data may be corrupt
};

class V4l2Stream {
 public:
  V4l2Stream(V4l2Io& io, const std::string& path);  // opens; InputError if it cannot
  ~V4l2Stream();                                    // stops streaming, unmaps, closes
  V4l2Stream(const V4l2Stream&) = delete;
  V4l2Stream& operator=(const V4l2Stream&) = delete;

  const std::string& path() const { return path_; }
  int fd() const { return fd_; }
  std::string driver() const { return driver_; }
  std::string card() const { return card_; }
  bool isVideoCapture() const;
  bool isMetaCapture() const;

  std::vector<V4l2FormatInfo> formats() const;  // of the node's capture type

  // Sets the pixel format and size; returns false (and changes nothing the caller relies on) when
  // the driver answers with another format or size. bytesPerLine()/imageBytes() then hold the
  // driver's layout.
  bool setVideoFormat(uint32_t fourcc, int width, int height);
  int bytesPerLine() const { return bytes_per_line_; }
  size_t imageBytes() const { return image_bytes_; }
  // Asks for `fps` frames per second; returns the rate the driver set (0 if it has no rate control).
  double setFrameRate(double fps);
  // Metadata nodes: selects the metadata format; false if the driver refuses it.
  bool setMetaFormat(uint32_t fourcc);

  // Allocates, maps and queues `count` buffers and starts streaming. InputError if it cannot.
  void start(int count);
  bool streaming() const { return streaming_; }

  // Takes the next filled buffer without blocking (wait on fd() with poll first). Returns false
  // when none is ready, or when the node is gone (then gone() is true and message() says why).
  bool dequeue(V4l2Buffer* buffer);
  // Gives a dequeued buffer back to the driver.
  void requeue(const V4l2Buffer& buffer);
  bool gone() const { return gone_; }
  const std::string& message() const { return message_; }

 private:
  uint32_t bufferType() const;
  void stop();
  void markGone(const std::string& what, int negative_errno);

  struct Mapping {
    void* address = nullptr;
    size_t length = 0;
  };
  V4l2Io& io_;
  std::string path_;
  int fd_ = -1;
  std::string driver_, card_;
  uint32_t device_caps_ = 0;
  int bytes_per_line_ = 0;
  size_t image_bytes_ = 0;
  std::vector<Mapping> buffers_;
  bool streaming_ = false;
  bool gone_ = false;
  std::string message_;
};

}  // namespace adugs::data

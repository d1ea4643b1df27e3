#include "data/device/v4l2_stream.h"

#include <cerrno>
#include <cstring>

#include <linux/videodev2.h>

#include "data/device/pixel_formats.h"
#include "data/input_error.h"

namespace adugs::data {
namespace {

std::string cString(const uint8_t* text, size_t size) {
  size_t n = 0;
  while (n < size && text[n]) ++n;
  return std::string(reinterpret_cast<const char*>(text), n);
}

}  // namespace

V4l2Stream::V4l2Stream(V4l2Io& io, const std::string& path) : io_(io), path_(path) {
  fd_ = io_.open(path);
  if (fd_ < 0) {
    const std::string hint = fd_ == -EACCES ? " (add yourself to the 'video' group or install the udev rule: README, "
                                              "\"Live on a D435i\")"
                                            : "";
    throw data::InputError(path, 0, "", "cannot open: " + errnoText(fd_) + hint);
  }
  v4l2_capability cap{};
  const int r = io_.ioctl(fd_, VIDIOC_QUERYCAP, &cap);
  if (r < 0) {
    io_.close(fd_);
    fd_ = -1;
    throw data::InputError(path, 0, "", "not a V4L2 device (VIDIOC_QUERYCAP: " + errnoText(r) + ")");
  }
  driver_ = cString(cap.driver, sizeof(cap.driver));
  card_ = cString(cap.card, sizeof(cap.card));
  device_caps_ = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
}

V4l2Stream::~V4l2Stream() {
  stop();
  if (fd_ >= 0) io_.close(fd_);
}

bool V4l2Stream::isVideoCapture() const { return device_caps_ & V4L2_CAP_VIDEO_CAPTURE; }
bool V4l2Stream::isMetaCapture() const { return device_caps_ & V4L2_CAP_META_CAPTURE; }

uint32_t V4l2Stream::bufferType() const {
  return isVideoCapture() ? V4L2_BUF_TYPE_VIDEO_CAPTURE : V4L2_BUF_TYPE_META_CAPTURE;
}

std::vector<V4l2FormatInfo> V4l2Stream::formats() const {
  std::vector<V4l2FormatInfo> out;
  for (uint32_t i = 0;; ++i) {
    v4l2_fmtdesc desc{};
    desc.index = i;
    desc.type = bufferType();
    if (io_.ioctl(fd_, VIDIOC_ENUM_FMT, &desc) < 0) break;
    V4l2FormatInfo f;
    f.fourcc = desc.pixelformat;
    f.description = cString(desc.description, sizeof(desc.description));
    for (uint32_t s = 0; isVideoCapture(); ++s) {
      v4l2_frmsizeenum size{};
      size.index = s;
      size.pixel_format = desc.pixelformat;
      if (io_.ioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &size) < 0 || size.type != V4L2_FRMSIZE_TYPE_DISCRETE) break;
      V4l2FrameSize fs;
      fs.width = static_cast<int>(size.discrete.width);
      fs.height = static_cast<int>(size.discrete.height);
      for (uint32_t k = 0;; ++k) {
        v4l2_frmivalenum interval{};
        interval.index = k;
        interval.pixel_format = desc.pixelformat;
        interval.width = size.discrete.width;
        interval.height = size.discrete.height;
        if (io_.ioctl(fd_, VIDIOC_ENUM_FRAMEINTERVALS, &interval) < 0 ||
            interval.type != V4L2_FRMIVAL_TYPE_DISCRETE || interval.discrete.numerator == 0)
          break;
        fs.rates_hz.push_back(static_cast<double>(interval.discrete.denominator) / interval.discrete.numerator);
      }
      f.sizes.push_back(fs);
    }
    out.push_back(f);
  }
  return out;
}

bool V4l2Stream::setVideoFormat(uint32_t fourcc, int width, int height) {
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.pixelformat = fourcc;
  fmt.fmt.pix.width = static_cast<uint32_t>(width);
  fmt.fmt.pix.height = static_cast<uint32_t>(height);
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  const int r = io_.ioctl(fd_, VIDIOC_S_FMT, &fmt);
  if (r < 0)
    throw data::InputError(path_, 0, "format", "VIDIOC_S_FMT " + data::fourccText(fourcc) + " " + std::to_string(width) +
                                                    "x" + std::to_string(height) + ": " + errnoText(r));
  if (fmt.fmt.pix.pixelformat != fourcc || fmt.fmt.pix.width != static_cast<uint32_t>(width) ||
      fmt.fmt.pix.height != static_cast<uint32_t>(height))
    return false;
  bytes_per_line_ = static_cast<int>(fmt.fmt.pix.bytesperline);
  image_bytes_ = fmt.fmt.pix.sizeimage;
  return true;
}

double V4l2Stream::setFrameRate(double fps) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = 1000;
  parm.parm.capture.timeperframe.denominator = static_cast<uint32_t>(fps * 1000.0 + 0.5);
  if (io_.ioctl(fd_, VIDIOC_S_PARM, &parm) < 0 || !(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) ||
      parm.parm.capture.timeperframe.numerator == 0)
    return 0.0;
  return static_cast<double>(parm.parm.capture.timeperframe.denominator) / parm.parm.capture.timeperframe.numerator;
}

bool V4l2Stream::setMetaFormat(uint32_t fourcc) {
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_META_CAPTURE;
  fmt.fmt.meta.dataformat = fourcc;
  if (io_.ioctl(fd_, VIDIOC_S_FMT, &fmt) < 0 || fmt.fmt.meta.dataformat != fourcc) return false;
  image_bytes_ = fmt.fmt.meta.buffersize;
  return true;
}

void V4l2Stream::start(int count) {
  v4l2_requestbuffers req{};
  req.count = static_cast<uint32_t>(count);
  req.type = bufferType();
  req.memory = V4L2_MEMORY_MMAP;
  int r = io_.ioctl(fd_, VIDIOC_REQBUFS, &req);
  if (r < 0) throw data::InputError(path_, 0, "buffers", "VIDIOC_REQBUFS (memory-mapped): " + errnoText(r));
  if (req.count < 2) throw data::InputError(path_, 0, "buffers", "the driver gave " + std::to_string(req.count) + " buffers");
  for (uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = req.type;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    r = io_.ioctl(fd_, VIDIOC_QUERYBUF, &buf);
    if (r < 0) throw data::InputError(path_, 0, "buffers", "VIDIOC_QUERYBUF: " + errnoText(r));
    void* address = io_.mmap(fd_, buf.length, buf.m.offset);
    if (!address) throw data::InputError(path_, 0, "buffers", "cannot map buffer " + std::to_string(i));
    buffers_.push_back({address, buf.length});
    r = io_.ioctl(fd_, VIDIOC_QBUF, &buf);
    if (r < 0) throw data::InputError(path_, 0, "buffers", "VIDIOC_QBUF: " + errnoText(r));
  }
  uint32_t type = req.type;
  r = io_.ioctl(fd_, VIDIOC_STREAMON, &type);
  if (r < 0) throw data::InputError(path_, 0, "", "VIDIOC_STREAMON: " + errnoText(r) + (r == -EBUSY ? " (is another program using the camera?)" : ""));
  streaming_ = true;
}

bool V4l2Stream::dequeue(V4l2Buffer* out) {
  if (gone_ || !streaming_) return false;
  v4l2_buffer buf{};
  buf.type = bufferType();
  buf.memory = V4L2_MEMORY_MMAP;
  const int r = io_.ioctl(fd_, VIDIOC_DQBUF, &buf);
  if (r == -EAGAIN) return false;
  if (r < 0) {
    markGone("VIDIOC_DQBUF", r);
    return false;
  }
  if (buf.index >= buffers_.size()) {
    markGone("VIDIOC_DQBUF returned buffer " + std::to_string(buf.index), -EINVAL);
    return false;
  }
  out->index = buf.index;
  out->data = static_cast<const uint8_t*>(buffers_[buf.index].address);
  out->bytes = std::min<size_t>(buf.bytesused, buffers_[buf.index].length);
  out->sequence = buf.sequence;
  out->timestamp_ns = static_cast<int64_t>(buf.timestamp.tv_sec) * 1'000'000'000 + static_cast<int64_t>(buf.timestamp.tv_usec) * 1000;
  out->monotonic = (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  out->error = buf.flags & V4L2_BUF_FLAG_ERROR;
  return true;
}

void V4l2Stream::requeue(const V4l2Buffer& buffer) {
  if (gone_) return;
  v4l2_buffer buf{};
  buf.type = bufferType();
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = buffer.index;
  const int r = io_.ioctl(fd_, VIDIOC_QBUF, &buf);
  if (r < 0) markGone("VIDIOC_QBUF", r);
}

void V4l2Stream::markGone(const std::string& what, int negative_errno) {
  gone_ = true;
  message_ = path_ + ": " + what + ": " + errnoText(negative_errno) +
             (negative_errno == -ENODEV ? " (camera unplugged?)" : "");
}

void V4l2Stream::stop() {
  if (streaming_) {
    uint32_t type = bufferType();
    io_.ioctl(fd_, VIDIOC_STREAMOFF, &type);  // fails harmlessly on an unplugged camera
    streaming_ = false;
  }
  for (const Mapping& m : buffers_) io_.munmap(m.address, m.length);
  buffers_.clear();
  if (fd_ >= 0) {
    v4l2_requestbuffers req{};  // free the driver's buffers so the next user can set a format
    req.count = 0;
    req.type = bufferType();
    req.memory = V4L2_MEMORY_MMAP;
    io_.ioctl(fd_, VIDIOC_REQBUFS, &req);
  }
}

}  // namespace adugs::data

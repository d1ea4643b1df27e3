#include "tests/data/live/fake_v4l2.h"

#include <cerrno>
#include <cmath>
#include <cstring>

#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <linux/videodev2.h>
#include <sys/eventfd.h>
#include <unistd.h>

namespace adugs::test {
namespace {

constexpr size_t kMetaBufferBytes = 4096;
constexpr uint64_t kOffsetStride = 1 << 24;  // QUERYBUF's m.offset: buffer index * stride

int bytesPerPixel(uint32_t fourcc) { return fourcc == v4l2_fourcc('G', 'R', 'E', 'Y') ? 1 : 2; }

void copyText(uint8_t* dst, size_t size, const std::string& text) {
  std::memset(dst, 0, size);
  std::memcpy(dst, text.data(), std::min(size - 1, text.size()));
}

const char* requestName(unsigned long request) {
  switch (request) {
    case VIDIOC_QUERYCAP: return "QUERYCAP";
    case VIDIOC_ENUM_FMT: return "ENUM_FMT";
    case VIDIOC_ENUM_FRAMESIZES: return "ENUM_FRAMESIZES";
    case VIDIOC_ENUM_FRAMEINTERVALS: return "ENUM_FRAMEINTERVALS";
    case VIDIOC_S_FMT: return "S_FMT";
    case VIDIOC_G_FMT: return "G_FMT";
    case VIDIOC_S_PARM: return "S_PARM";
    case VIDIOC_REQBUFS: return "REQBUFS";
    case VIDIOC_QUERYBUF: return "QUERYBUF";
    case VIDIOC_QBUF: return "QBUF";
    case VIDIOC_DQBUF: return "DQBUF";
    case VIDIOC_STREAMON: return "STREAMON";
    case VIDIOC_STREAMOFF: return "STREAMOFF";
    case VIDIOC_S_CTRL: return "S_CTRL";
    case VIDIOC_G_CTRL: return "G_CTRL";
    case UVCIOC_CTRL_QUERY: return "UVCIOC_CTRL_QUERY";
    default: return "?";
  }
}

}  // namespace

FakeV4l2::~FakeV4l2() {
  for (auto& [path, n] : nodes_)
    if (n.fd >= 0) ::close(n.fd);
}

void FakeV4l2::addVideoNode(const std::string& path, const std::vector<FakeFormat>& formats, const std::string& card) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node& n = nodes_[path];
  n.meta = false;
  n.card = card;
  n.formats = formats;
  // A D4xx powers up with the emitter on, auto exposure on.
  n.state.xu[2] = {1};
  n.state.xu[3] = {0x10, 0x27, 0, 0};  // 10000 us
  n.state.xu[0x0B] = {1};
  n.state.controls[V4L2_CID_GAIN] = 16;
}

void FakeV4l2::addMetaNode(const std::string& path, const std::vector<uint32_t>& meta_formats) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node& n = nodes_[path];
  n.meta = true;
  n.card = "Intel(R) RealSense(TM) Depth Ca";
  n.meta_formats = meta_formats;
}

FakeV4l2::State FakeV4l2::state(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  return nodes_.at(path).state;
}

FakeV4l2::Node* FakeV4l2::nodeOfFd(int fd) {
  for (auto& [path, n] : nodes_)
    if (n.fd == fd && fd >= 0) return &n;
  return nullptr;
}

int FakeV4l2::open(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = nodes_.find(path);
  if (it == nodes_.end()) return -ENOENT;
  Node& n = it->second;
  if (n.gone) return -ENODEV;
  if (n.fd >= 0) return -EBUSY;  // one user at a time is all these tests need
  n.fd = eventfd(0, EFD_NONBLOCK | EFD_SEMAPHORE | EFD_CLOEXEC);
  ++n.state.open_count;
  return n.fd;
}

void FakeV4l2::close(int fd) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node* n = nodeOfFd(fd);
  if (!n) return;
  ::close(n->fd);
  n->fd = -1;
  n->state.streaming = false;
  n->buffers.clear();
  n->queued.clear();
  n->done.clear();
}

void* FakeV4l2::mmap(int fd, size_t length, int64_t offset) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node* n = nodeOfFd(fd);
  const size_t index = static_cast<size_t>(offset) / kOffsetStride;
  if (!n || index >= n->buffers.size() || length != n->buffers[index].data.size()) return nullptr;
  return n->buffers[index].data.data();
}

void FakeV4l2::munmap(void*, size_t) {}

int FakeV4l2::ioctl(int fd, unsigned long request, void* arg) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node* n = nodeOfFd(fd);
  if (!n) return -EBADF;
  n->state.calls.push_back(requestName(request));
  if (n->gone) return -ENODEV;
  return handle(*n, request, arg);
}

int FakeV4l2::handle(Node& n, unsigned long request, void* arg) {
  const uint32_t type = n.meta ? V4L2_BUF_TYPE_META_CAPTURE : V4L2_BUF_TYPE_VIDEO_CAPTURE;
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      std::memset(cap, 0, sizeof(*cap));
      copyText(cap->driver, sizeof(cap->driver), "uvcvideo");
      copyText(cap->card, sizeof(cap->card), n.card);
      cap->device_caps = (n.meta ? V4L2_CAP_META_CAPTURE : V4L2_CAP_VIDEO_CAPTURE) | V4L2_CAP_STREAMING;
      cap->capabilities = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_META_CAPTURE | V4L2_CAP_STREAMING | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* d = static_cast<v4l2_fmtdesc*>(arg);
      if (d->type != type) return -EINVAL;
      const size_t count = n.meta ? n.meta_formats.size() : n.formats.size();
      if (d->index >= count) return -EINVAL;
      d->pixelformat = n.meta ? n.meta_formats[d->index] : n.formats[d->index].fourcc;
      copyText(d->description, sizeof(d->description), n.meta ? "metadata" : n.formats[d->index].description);
      return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
      auto* s = static_cast<v4l2_frmsizeenum*>(arg);
      for (const FakeFormat& f : n.formats) {
        if (f.fourcc != s->pixel_format) continue;
        if (s->index >= f.sizes.size()) return -EINVAL;
        s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
        s->discrete.width = static_cast<uint32_t>(f.sizes[s->index].width);
        s->discrete.height = static_cast<uint32_t>(f.sizes[s->index].height);
        return 0;
      }
      return -EINVAL;
    }
    case VIDIOC_ENUM_FRAMEINTERVALS: {
      auto* i = static_cast<v4l2_frmivalenum*>(arg);
      for (const FakeFormat& f : n.formats) {
        if (f.fourcc != i->pixel_format) continue;
        for (const FakeFrameSize& z : f.sizes) {
          if (z.width != static_cast<int>(i->width) || z.height != static_cast<int>(i->height)) continue;
          if (i->index >= z.rates_hz.size()) return -EINVAL;
          i->type = V4L2_FRMIVAL_TYPE_DISCRETE;
          i->discrete.numerator = 1000;
          i->discrete.denominator = static_cast<uint32_t>(std::lround(z.rates_hz[i->index] * 1000));
          return 0;
        }
      }
      return -EINVAL;
    }
    case VIDIOC_S_FMT:
    case VIDIOC_G_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != type) return -EINVAL;
      if (n.state.streaming && request == VIDIOC_S_FMT) return -EBUSY;
      if (n.meta) {
        if (request == VIDIOC_S_FMT) {
          bool known = false;
          for (uint32_t m : n.meta_formats) known = known || m == f->fmt.meta.dataformat;
          // The driver keeps its current format when asked for one it does not have.
          if (known) n.state.meta_format = f->fmt.meta.dataformat;
          else if (n.state.meta_format == 0) n.state.meta_format = n.meta_formats.front();
        }
        f->fmt.meta.dataformat = n.state.meta_format;
        f->fmt.meta.buffersize = kMetaBufferBytes;
        return 0;
      }
      if (request == VIDIOC_S_FMT) {
        // As drivers do: the nearest thing they have (here: the first format and size) if not listed.
        const FakeFormat* chosen = &n.formats.front();
        for (const FakeFormat& fm : n.formats)
          if (fm.fourcc == f->fmt.pix.pixelformat) chosen = &fm;
        const FakeFrameSize* size = &chosen->sizes.front();
        for (const FakeFrameSize& z : chosen->sizes)
          if (z.width == static_cast<int>(f->fmt.pix.width) && z.height == static_cast<int>(f->fmt.pix.height)) size = &z;
        n.state.fourcc = chosen->fourcc;
        n.state.width = size->width;
        n.state.height = size->height;
      }
      f->fmt.pix.pixelformat = n.state.fourcc;
      f->fmt.pix.width = static_cast<uint32_t>(n.state.width);
      f->fmt.pix.height = static_cast<uint32_t>(n.state.height);
      f->fmt.pix.bytesperline = static_cast<uint32_t>(n.state.width * bytesPerPixel(n.state.fourcc));
      f->fmt.pix.sizeimage = f->fmt.pix.bytesperline * static_cast<uint32_t>(n.state.height);
      return 0;
    }
    case VIDIOC_S_PARM: {
      auto* p = static_cast<v4l2_streamparm*>(arg);
      if (n.meta || p->type != type) return -EINVAL;
      const double want = p->parm.capture.timeperframe.numerator
                              ? static_cast<double>(p->parm.capture.timeperframe.denominator) / p->parm.capture.timeperframe.numerator
                              : 30.0;
      double best = 0;
      for (const FakeFormat& f : n.formats)
        if (f.fourcc == n.state.fourcc)
          for (const FakeFrameSize& z : f.sizes)
            if (z.width == n.state.width && z.height == n.state.height)
              for (double r : z.rates_hz)
                if (best == 0 || std::abs(r - want) < std::abs(best - want)) best = r;
      n.state.fps = best;
      p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      p->parm.capture.timeperframe.numerator = 1000;
      p->parm.capture.timeperframe.denominator = static_cast<uint32_t>(std::lround(best * 1000));
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != type || r->memory != V4L2_MEMORY_MMAP) return -EINVAL;
      if (n.state.streaming) return -EBUSY;
      const size_t bytes = n.meta ? kMetaBufferBytes
                                  : static_cast<size_t>(n.state.width) * n.state.height * bytesPerPixel(n.state.fourcc);
      if (!n.meta && bytes == 0) return -EINVAL;  // no format set
      r->count = std::min<uint32_t>(r->count, 32);
      n.buffers.assign(r->count, Buffer{});
      for (Buffer& b : n.buffers) b.data.assign(bytes, 0);
      n.queued.clear();
      n.done.clear();
      n.state.buffers = r->count;
      return 0;
    }
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != type || b->memory != V4L2_MEMORY_MMAP) return -EINVAL;
      if (request == VIDIOC_DQBUF) {
        if (n.done.empty()) return -EAGAIN;
        uint64_t count = 0;
        if (::read(n.fd, &count, sizeof(count)) < 0) {  // one filled buffer less to poll for
        }
        const uint32_t index = n.done.front();
        n.done.pop_front();
        const Buffer& buf = n.buffers[index];
        b->index = index;
        b->bytesused = buf.bytesused;
        b->sequence = buf.sequence;
        b->flags = buf.flags | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        b->timestamp.tv_sec = buf.timestamp_ns / 1'000'000'000;
        b->timestamp.tv_usec = (buf.timestamp_ns % 1'000'000'000) / 1000;
        return 0;
      }
      if (b->index >= n.buffers.size()) return -EINVAL;
      if (request == VIDIOC_QUERYBUF) {
        b->length = static_cast<uint32_t>(n.buffers[b->index].data.size());
        b->m.offset = static_cast<uint32_t>(b->index * kOffsetStride);
        return 0;
      }
      for (uint32_t q : n.queued)
        if (q == b->index) return -EINVAL;  // queued twice
      n.queued.push_back(b->index);
      return 0;
    }
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
      if (*static_cast<uint32_t*>(arg) != type) return -EINVAL;
      if (request == VIDIOC_STREAMON && n.buffers.empty()) return -EINVAL;
      n.state.streaming = request == VIDIOC_STREAMON;
      if (!n.state.streaming) {
        n.queued.clear();
        n.done.clear();
      }
      return 0;
    }
    case VIDIOC_S_CTRL:
    case VIDIOC_G_CTRL: {
      if (n.meta) return -ENOTTY;
      auto* c = static_cast<v4l2_control*>(arg);
      if (request == VIDIOC_S_CTRL) n.state.controls[c->id] = c->value;
      else if (n.state.controls.count(c->id)) c->value = n.state.controls[c->id];
      else return -EINVAL;
      return 0;
    }
    case UVCIOC_CTRL_QUERY: {
      if (n.meta) return -ENOTTY;
      auto* q = static_cast<uvc_xu_control_query*>(arg);
      if (q->unit != 3) return -ENOENT;
      const auto it = n.state.xu.find(q->selector);
      if (it == n.state.xu.end()) return -ENOENT;
      if (q->size != it->second.size()) return -ENOBUFS;
      if (q->query == UVC_SET_CUR) it->second.assign(q->data, q->data + q->size);
      else if (q->query == UVC_GET_CUR) std::memcpy(q->data, it->second.data(), q->size);
      else return -EINVAL;
      return 0;
    }
    default:
      return -ENOTTY;
  }
}

bool FakeV4l2::deliver(const std::string& path, const std::vector<uint8_t>& bytes, int64_t timestamp_ns, bool error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node& n = nodes_.at(path);
  if (n.gone || !n.state.streaming) return false;
  const uint32_t sequence = n.state.sequence++;
  if (n.queued.empty()) return false;  // the driver had no buffer: the frame is lost
  const uint32_t index = n.queued.front();
  n.queued.pop_front();
  Buffer& b = n.buffers[index];
  const size_t count = std::min(bytes.size(), b.data.size());
  std::memcpy(b.data.data(), bytes.data(), count);
  b.bytesused = static_cast<uint32_t>(count);
  b.sequence = sequence;
  b.timestamp_ns = timestamp_ns;
  b.flags = error ? V4L2_BUF_FLAG_ERROR : 0;
  n.done.push_back(index);
  const uint64_t one = 1;
  if (::write(n.fd, &one, sizeof(one)) < 0) {
  }
  return true;
}

void FakeV4l2::unplug(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  Node& n = nodes_.at(path);
  n.gone = true;
  n.state.streaming = false;
  const uint64_t wake = 1000;
  if (n.fd >= 0 && ::write(n.fd, &wake, sizeof(wake)) < 0) {
  }
}

}  // namespace adugs::test

#include "data/device/v4l2_io.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace adugs::data {
namespace {

class SystemV4l2Io : public V4l2Io {
 public:
  int open(const std::string& path) override {
    const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    return fd >= 0 ? fd : -errno;
  }
  void close(int fd) override { ::close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override {
    int r;
    do {
      r = ::ioctl(fd, request, arg);
    } while (r < 0 && errno == EINTR);
    return r < 0 ? -errno : 0;
  }
  void* mmap(int fd, size_t length, int64_t offset) override {
    void* p = ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, static_cast<off_t>(offset));
    return p == MAP_FAILED ? nullptr : p;
  }
  void munmap(void* address, size_t length) override { ::munmap(address, length); }
};

}  // namespace

V4l2Io& systemV4l2Io() {
  static SystemV4l2Io io;
  return io;
}

std::string errnoText(int negative_errno) { return std::strerror(-negative_errno); }

}  // namespace adugs::data

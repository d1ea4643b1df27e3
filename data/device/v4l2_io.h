#pragma once
// The thin layer between the live capture code and the kernel: the system calls a V4L2 client
// makes, and nothing else. Everything above it (format negotiation, streaming buffers, UVC
// extension-unit controls, the D435i source) talks to the kernel only through this interface, so
// tests drive it with a fake kernel; the system implementation below is the only untested part.
#include <cstddef>
#include <cstdint>
#include <string>

namespace adugs::data {

class V4l2Io {
 public:
  virtual ~V4l2Io() = default;
  // Opens a device node read-write and non-blocking: a file descriptor that poll(2) can wait on
  // (readable when a buffer can be dequeued), or -errno.
  virtual int open(const std::string& path) = 0;
  virtual void close(int fd) = 0;
  // ioctl(2), retried on EINTR: 0 or -errno.
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  // mmap(2) of a driver buffer (read-write, shared); nullptr on failure.
  virtual void* mmap(int fd, size_t length, int64_t offset) = 0;
  virtual void munmap(void* address, size_t length) = 0;
};

// The real system calls.
V4l2Io& systemV4l2Io();

// strerror(-code) for the -errno values above.
std::string errnoText(int negative_errno);

}  // namespace adugs::data

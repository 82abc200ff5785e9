#pragma once
// RAII for the C handles of a V4L2 capture: the device's file descriptor (base/unique_fd.hpp)
// and its mmap'd buffers, plus an ioctl that survives signals. Internal to drivers/v4l2.
#include <cstddef>
#include <string>
#include <utility>

#include "base/unique_fd.hpp"

namespace probeless::v4l2 {

// ioctl() retried on EINTR (a signal during a blocking call is not a failure). Returns 0 or
// -1 with errno set, like ioctl.
int xioctl(int fd, unsigned long request, void* arg);

// "VIDIOC_DQBUF: No such device" for error messages.
std::string errno_text(const char* what, int err);

// One driver buffer mapped into our address space; unmapped on destruction. Must not outlive
// the open file it was mapped from only by convention: munmap works either way, and the
// driver keeps the memory until the last mapping goes.
class MappedBuffer {
 public:
  MappedBuffer() = default;
  // Throws std::runtime_error when mmap fails.
  MappedBuffer(int fd, std::size_t length, long offset);
  ~MappedBuffer() { reset(); }
  MappedBuffer(MappedBuffer&& o) noexcept
      : data_(std::exchange(o.data_, nullptr)), length_(std::exchange(o.length_, 0)) {}
  MappedBuffer& operator=(MappedBuffer&& o) noexcept {
    if (this != &o) {
      reset();
      data_ = std::exchange(o.data_, nullptr);
      length_ = std::exchange(o.length_, 0);
    }
    return *this;
  }
  MappedBuffer(const MappedBuffer&) = delete;
  MappedBuffer& operator=(const MappedBuffer&) = delete;

  const unsigned char* data() const { return static_cast<const unsigned char*>(data_); }
  std::size_t length() const { return length_; }
  void reset();

 private:
  void* data_ = nullptr;
  std::size_t length_ = 0;
};

}  // namespace probeless::v4l2

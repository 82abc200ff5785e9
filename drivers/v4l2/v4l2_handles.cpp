#include "drivers/v4l2/v4l2_handles.hpp"

#include <sys/ioctl.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace probeless::v4l2 {

int xioctl(int fd, unsigned long request, void* arg) {
  int r = 0;
  do {
    r = ::ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

std::string errno_text(const char* what, int err) {
  return std::string(what) + ": " + std::strerror(err);
}

MappedBuffer::MappedBuffer(int fd, std::size_t length, long offset) : length_(length) {
  data_ = ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
  if (data_ == MAP_FAILED) {
    data_ = nullptr;
    length_ = 0;
    throw std::runtime_error(errno_text("mmap of a V4L2 buffer", errno));
  }
}

void MappedBuffer::reset() {
  if (data_ != nullptr) ::munmap(data_, length_);
  data_ = nullptr;
  length_ = 0;
}

}  // namespace probeless::v4l2

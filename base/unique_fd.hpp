#pragma once
// An owned file descriptor (a V4L2 device, a DRM card): closed on destruction, movable, not
// copyable. release() hands the descriptor over to a caller that closes it itself.
#include <utility>

namespace probeless {

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd() { reset(); }
  UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) reset(o.release());
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;

  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  [[nodiscard]] int release() { return std::exchange(fd_, -1); }
  // Closes the descriptor held (if any) and takes `fd` (-1: none).
  void reset(int fd = -1);

 private:
  int fd_ = -1;
};

}  // namespace probeless

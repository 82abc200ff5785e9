#include "base/unique_fd.hpp"

#include <unistd.h>

namespace probeless {

void UniqueFd::reset(int fd) {
  // close() is not retried on EINTR: Linux releases the descriptor either way, and a retry
  // could close one another thread has just been given.
  if (fd_ >= 0 && fd_ != fd) ::close(fd_);
  fd_ = fd;
}

}  // namespace probeless

#include "app/service/signals.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <stdexcept>
#include <system_error>

namespace probeless {
namespace {

// What the handler may touch: lock-free atomics only.
std::atomic<int> g_pipe_write{-1};
std::atomic<bool> g_instance{false};
static_assert(std::atomic<int>::is_always_lock_free);

constexpr unsigned char kQuitByte = 0;  // from the destructor; signal numbers are > 0

extern "C" void on_shutdown_signal(int signo) {
  const int saved_errno = errno;
  const int fd = g_pipe_write.load(std::memory_order_relaxed);
  if (fd >= 0) {
    const auto byte = static_cast<unsigned char>(signo);
    [[maybe_unused]] const ssize_t n = ::write(fd, &byte, 1);  // full pipe: already woken
  }
  errno = saved_errno;
}

[[noreturn]] void throw_errno(const char* what) {
  throw std::system_error(errno, std::generic_category(), what);
}

}  // namespace

void ShutdownSignals::MarkStopped::operator()() const noexcept {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(fd, &one, sizeof one);
}

ShutdownSignals::ShutdownSignals(std::initializer_list<int> signals) {
  if (g_instance.exchange(true)) {
    throw std::logic_error("ShutdownSignals: only one instance may exist at a time");
  }
  try {
    int fds[2];
    if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw_errno("pipe2");
    pipe_read_ = fds[0];
    pipe_write_ = fds[1];
    stopped_fd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (stopped_fd_ < 0) throw_errno("eventfd");
    on_stop_.emplace(source_.get_token(), MarkStopped{stopped_fd_});
    watcher_ = std::thread([this] { watch(); });
    g_pipe_write.store(pipe_write_);

    struct sigaction action {};
    action.sa_handler = on_shutdown_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART | SA_RESETHAND;
    for (int signo : signals) {
      struct sigaction old {};
      if (::sigaction(signo, &action, &old) != 0) throw_errno("sigaction");
      previous_.emplace_back(signo, old);
    }
  } catch (...) {
    release();
    throw;
  }
}

ShutdownSignals::~ShutdownSignals() {
  release();
}

void ShutdownSignals::release() noexcept {
  for (const auto& [signo, old] : previous_) ::sigaction(signo, &old, nullptr);
  previous_.clear();
  g_pipe_write.store(-1);
  if (watcher_.joinable()) {
    // A blocking write would be wrong in a destructor, but the pipe is never full here: the
    // watcher drains it, and the handler is uninstalled.
    const unsigned char quit = kQuitByte;
    while (::write(pipe_write_, &quit, 1) < 0 && errno == EINTR) {
    }
    watcher_.join();
  }
  on_stop_.reset();
  for (int* fd : {&pipe_read_, &pipe_write_, &stopped_fd_}) {
    if (*fd >= 0) ::close(*fd);
    *fd = -1;
  }
  g_instance.store(false);
}

void ShutdownSignals::watch() {
  pollfd p{pipe_read_, POLLIN, 0};
  for (;;) {
    if (::poll(&p, 1, -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    unsigned char bytes[64];
    const ssize_t n = ::read(pipe_read_, bytes, sizeof bytes);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return;
    for (ssize_t i = 0; i < n; ++i) {
      if (bytes[i] == kQuitByte) return;
      int expected = 0;
      signal_.compare_exchange_strong(expected, bytes[i]);
      source_.request_stop();
    }
  }
}

bool ShutdownSignals::wait_for(std::chrono::milliseconds timeout) const {
  if (stop_requested()) return true;
  pollfd p{stopped_fd_, POLLIN, 0};
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    const int r = ::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(left.count(), 0)));
    if (r > 0 || stop_requested()) return true;
    if (r == 0) return false;
    if (errno != EINTR) return stop_requested();
  }
}

}  // namespace probeless

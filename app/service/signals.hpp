#pragma once
// SIGTERM (systemctl stop) and SIGINT (Ctrl-C) as a stop request. The handler does only
// async-signal-safe work: it stores the signal number and writes one byte to a pipe. A
// small watcher thread turns that byte into std::stop_source::request_stop(), so the rest
// of the service sees an ordinary std::stop_token (for std::jthread, condition_variable_any,
// LatestFrame::wait_newer) or a file descriptor to poll, and never a signal.
//
// A second SIGTERM/SIGINT while shutting down gets the default action (the process dies):
// the handlers are installed with SA_RESETHAND, so a hung shutdown can still be interrupted.
#include <atomic>
#include <chrono>
#include <csignal>
#include <initializer_list>
#include <optional>
#include <stop_token>
#include <thread>
#include <vector>

namespace probeless {

class ShutdownSignals {
 public:
  // Installs the handlers; the destructor restores the previous ones. One instance at a
  // time in a process (the handler has one pipe): a second throws std::logic_error.
  explicit ShutdownSignals(std::initializer_list<int> signals = {SIGTERM, SIGINT});
  ~ShutdownSignals();
  ShutdownSignals(const ShutdownSignals&) = delete;
  ShutdownSignals& operator=(const ShutdownSignals&) = delete;
  ShutdownSignals(ShutdownSignals&&) = delete;
  ShutdownSignals& operator=(ShutdownSignals&&) = delete;

  std::stop_token token() const { return source_.get_token(); }
  bool stop_requested() const { return source_.stop_requested(); }
  // The same stop from code (frame limit reached, fatal error): everyone wakes alike.
  void request_stop() { source_.request_stop(); }
  // The signal that asked for the stop; 0 while none has (or when code asked).
  int signal_number() const { return signal_.load(); }

  // Becomes readable, and stays readable, once a stop is requested: poll() it beside other
  // descriptors. Do not read from it.
  int fd() const { return stopped_fd_; }
  // Waits until a stop is requested or the timeout passes; true if stop was requested.
  bool wait_for(std::chrono::milliseconds timeout) const;

 private:
  void watch();
  void release() noexcept;  // the destructor's work, also for a constructor that fails
  struct MarkStopped {      // the stop callback: makes fd() readable
    int fd;
    void operator()() const noexcept;
  };

  std::stop_source source_;
  std::atomic<int> signal_{0};
  int pipe_read_ = -1;
  int pipe_write_ = -1;
  int stopped_fd_ = -1;  // eventfd
  std::vector<std::pair<int, struct sigaction>> previous_;
  std::optional<std::stop_callback<MarkStopped>> on_stop_;
  std::thread watcher_;
};

}  // namespace probeless

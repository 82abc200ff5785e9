#pragma once
// A child process for end-to-end tests: the real `probeless` binary, its stdout read line by
// line, signals sent to it, its exit awaited with a timeout. Killed when the object dies.
#include <sys/types.h>

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace probeless::testing {

class Subprocess {
 public:
  // argv[0] is the program path. `env` entries are added to (or replace) the environment.
  // With merge_stderr, the child's stderr (its log and error messages) joins stdout.
  Subprocess(std::vector<std::string> argv, std::map<std::string, std::string> env = {},
             bool merge_stderr = false);
  ~Subprocess();
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  // The next line of stdout containing `needle`, or nullopt at EOF or timeout.
  std::optional<std::string> wait_for_line(const std::string& needle,
                                           std::chrono::milliseconds timeout);
  void send_signal(int signal);
  // Exit status (WEXITSTATUS, or 128 + signal) or nullopt on timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  pid_t pid() const { return pid_; }
  const std::string& output() const { return output_; }  // all stdout read so far

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::string buffer_;
  std::string output_;
  std::optional<int> status_;
};

// The probeless binary under test: $PROBELESS_BINARY (set at start-up by test_data.cpp).
std::string probeless_binary();

// Runs `program args` to its end, stdout and stderr together in `output`; returns the exit
// status, or -1 if it did not end within `timeout`.
int run_to_end(const std::string& program, const std::vector<std::string>& args,
               std::string* output, std::chrono::seconds timeout);

}  // namespace probeless::testing

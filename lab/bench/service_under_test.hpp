#pragma once
// A `probeless run` child process for the benches that load the service from outside
// (`bench http`, `bench soak`): started with the appliance binary beside the lab's, on an
// ephemeral loopback port, and watched through /proc (resident memory, descriptors, threads)
// and its own GET /status.
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace probeless::lab {

struct ProcessSample {
  double rss_mb = 0;  // VmRSS
  int fds = 0;        // entries of /proc/PID/fd
  int threads = 0;    // Threads
  double cpu_s = 0;   // utime + stime
};

// /proc/PID of any process; throws std::runtime_error when it is gone.
ProcessSample sample_process(pid_t pid);

// The appliance binary: beside this (lab) binary in the build tree, or ../../bin/probeless
// from /usr/lib/probeless/probeless-lab in an install.
std::filesystem::path appliance_binary();

class ServiceUnderTest {
 public:
  // Starts `probeless run --port 0 ARGS...` (at `nice_level` above this process; with its
  // descriptor limit set to `nofile` when > 0, as a unit's LimitNOFILE would) and waits for
  // its "serving http://..." line; throws std::runtime_error with its output otherwise.
  explicit ServiceUnderTest(std::vector<std::string> args, int nice_level = 0, int nofile = 0,
                            std::chrono::seconds start_timeout = std::chrono::seconds(120));
  ~ServiceUnderTest();  // SIGTERM, then SIGKILL after 10 s
  ServiceUnderTest(const ServiceUnderTest&) = delete;
  ServiceUnderTest& operator=(const ServiceUnderTest&) = delete;

  pid_t pid() const { return pid_; }
  int port() const { return port_; }
  bool alive() const;
  ProcessSample sample() const { return sample_process(pid_); }
  // GET /status as JSON (throws on failure).
  nlohmann::json status() const;
  // frames.processed from /status.
  std::uint64_t frames_processed() const;

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  int output_fd_ = -1;
};

// A blocking GET over loopback; the whole response (headers and body), throws on failure.
std::string http_get(int port, const std::string& path,
                     std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

// The body of an HTTP response (after the blank line).
std::string http_body(const std::string& response);

}  // namespace probeless::lab

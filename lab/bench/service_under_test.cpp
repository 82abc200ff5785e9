#include "lab/bench/service_under_test.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace probeless::lab {
namespace {

using Clock = std::chrono::steady_clock;

int remaining_ms(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return left.count() > 0 ? static_cast<int>(left.count()) : 0;
}

}  // namespace

ProcessSample sample_process(pid_t pid) {
  const std::string dir = "/proc/" + std::to_string(pid);
  std::ifstream status(dir + "/status");
  if (!status) throw std::runtime_error("process " + std::to_string(pid) + " is gone");
  ProcessSample s;
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) s.rss_mb = std::stod(line.substr(6)) / 1024.0;
    if (line.rfind("Threads:", 0) == 0) s.threads = std::stoi(line.substr(8));
  }
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator(dir + "/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++s.fds;
  std::ifstream stat(dir + "/stat");
  std::string text;
  std::getline(stat, text);  // one line
  // Fields after the command name (which may hold spaces): state is field 3, utime 14, stime 15.
  std::istringstream rest(text.substr(text.rfind(')') + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 15 && rest >> field; ++i)
    if (i >= 14) ticks += std::stod(field);
  s.cpu_s = ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
  return s;
}

std::filesystem::path appliance_binary() {
  const auto self = std::filesystem::read_symlink("/proc/self/exe");
  for (const auto& candidate :
       {self.parent_path() / "probeless", self.parent_path() / "../../bin/probeless"}) {
    if (std::filesystem::exists(candidate)) return candidate;
  }
  throw std::runtime_error("no probeless binary beside " + self.string());
}

ServiceUnderTest::ServiceUnderTest(std::vector<std::string> args, int nice_level, int nofile,
                                   std::chrono::seconds start_timeout) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  const std::string binary = appliance_binary().string();
  args.insert(args.begin(), {binary, "run", "--port", "0"});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_ = fork();
  if (pid_ == 0) {
    // A bench killed before its destructor runs (SIGPIPE into a closed pager, Ctrl-C) must
    // not leave a service loading the machine for the next measurement.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    dup2(pipe_fds[1], STDOUT_FILENO);
    if (nice_level > 0 && nice(nice_level) < 0) _exit(126);
    const rlimit limit{static_cast<rlim_t>(nofile), static_cast<rlim_t>(nofile)};
    if (nofile > 0 && setrlimit(RLIMIT_NOFILE, &limit) != 0) _exit(126);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  close(pipe_fds[1]);
  output_fd_ = pipe_fds[0];
  if (pid_ < 0) throw std::runtime_error("fork failed");

  std::string output;
  const auto deadline = Clock::now() + start_timeout;
  while (port_ == 0) {
    pollfd p{output_fd_, POLLIN, 0};
    if (poll(&p, 1, remaining_ms(deadline)) <= 0) break;
    char buf[512];
    const ssize_t n = read(output_fd_, buf, sizeof buf);
    if (n <= 0) break;
    output.append(buf, static_cast<std::size_t>(n));
    if (const auto at = output.find("serving http://"); at != std::string::npos) {
      const auto colon = output.find(':', at + 15);
      const auto slash = output.find('/', colon);
      if (colon != std::string::npos && slash != std::string::npos)
        port_ = std::stoi(output.substr(colon + 1, slash - colon - 1));
    }
  }
  if (port_ == 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    close(output_fd_);
    throw std::runtime_error(binary + " run did not start serving; it printed:\n" + output);
  }
  // Keep reading its output so that it never blocks on a full pipe.
  std::thread([fd = output_fd_] {
    char buf[4096];
    while (read(fd, buf, sizeof buf) > 0) {
    }
    close(fd);
  }).detach();
}

ServiceUnderTest::~ServiceUnderTest() {
  if (pid_ <= 0) return;
  kill(pid_, SIGTERM);
  for (int i = 0; i < 1000; ++i) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
}

bool ServiceUnderTest::alive() const {
  return kill(pid_, 0) == 0 && waitpid(pid_, nullptr, WNOHANG) == 0;
}

nlohmann::json ServiceUnderTest::status() const {
  return nlohmann::json::parse(http_body(http_get(port_, "/status")));
}

std::uint64_t ServiceUnderTest::frames_processed() const {
  return status()["frames"].value("processed", std::uint64_t{0});
}

std::string http_get(int port, const std::string& path, std::chrono::milliseconds timeout) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  timeval tv{static_cast<time_t>(timeout.count() / 1000),
             static_cast<suseconds_t>(timeout.count() % 1000 * 1000)};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    throw std::runtime_error("connect to port " + std::to_string(port) + ": " +
                             std::strerror(errno));
  const std::string request =
      "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  if (send(fd, request.data(), request.size(), MSG_NOSIGNAL) !=
      static_cast<ssize_t>(request.size()))
    throw std::runtime_error("send " + path + ": " + std::strerror(errno));
  std::string response;
  char buf[8192];
  for (;;) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n == 0) break;
    if (n < 0) throw std::runtime_error("GET " + path + ": " + std::strerror(errno));
    response.append(buf, static_cast<std::size_t>(n));
  }
  return response;
}

std::string http_body(const std::string& response) {
  const auto at = response.find("\r\n\r\n");
  return at == std::string::npos ? std::string() : response.substr(at + 4);
}

}  // namespace probeless::lab

// Socket activation (issue #20 item 7, docs/appliance.md "Socket activation"): the real
// binary started as systemd starts it for probeless.socket, with a listening socket at
// SD_LISTEN_FDS_START and LISTEN_FDS/LISTEN_PID naming it, must serve HTTP on that socket.
// The VM test vm_systemd_unit does the same through a real systemd.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "support/http_client.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {
namespace {

using namespace std::chrono_literals;

// A TCP socket listening on an ephemeral loopback port.
int listening_socket(int& port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(fd, 16) != 0)
    return -1;
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  port = ntohs(addr.sin_port);
  return fd;
}

// Starts `probeless run ARGS` with `fds` at 3, 4, ... and LISTEN_FDS/LISTEN_PID set, as
// systemd's exec does; stdout and stderr to `log`.
pid_t start_activated(const std::vector<int>& fds, const std::vector<std::string>& args,
                      const std::filesystem::path& log) {
  std::vector<std::string> argv{probeless_binary(), "run"};
  argv.insert(argv.end(), args.begin(), args.end());
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(out, 1);
  ::dup2(out, 2);
  // Move the sockets above the targets first, so a dup2 never closes one not yet moved.
  std::vector<int> high;
  for (int fd : fds) high.push_back(::fcntl(fd, F_DUPFD, 100));
  for (std::size_t i = 0; i < high.size(); ++i) ::dup2(high[i], 3 + static_cast<int>(i));
  ::setenv("LISTEN_FDS", std::to_string(fds.size()).c_str(), 1);
  ::setenv("LISTEN_PID", std::to_string(::getpid()).c_str(), 1);
  std::vector<char*> c;
  for (auto& a : argv) c.push_back(a.data());
  c.push_back(nullptr);
  ::execv(c[0], c.data());
  ::_exit(127);
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

int wait_exit(pid_t pid, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (::waitpid(pid, &status, WNOHANG) == pid)
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::this_thread::sleep_for(50ms);
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -1;
}

TEST(SocketActivation, ServesHttpOnTheSocketSystemdPassed) {
  int port = 0;
  const int fd = listening_socket(port);
  ASSERT_GE(fd, 0);
  const auto log = scratch_dir() / "activated.log";
  // --port names another port: the passed socket must win over it.
  const pid_t pid = start_activated({fd}, {"--source", "sim:realtime=0", "--port", "1"}, log);
  ::close(fd);
  nlohmann::json status;
  // A cold PoCL cache on a busy host takes minutes to compile the kernels.
  const auto deadline = std::chrono::steady_clock::now() + 300s;
  while (std::chrono::steady_clock::now() < deadline) {
    try {
      const auto r = loopback::http_get(port, "/status");
      if (r.status == 200) {
        status = nlohmann::json::parse(r.body);
        if (status["frames"]["out"].get<int>() > 0) break;
      }
    } catch (const std::runtime_error&) {
      // not accepting yet (the socket queues the connection until the service serves it)
    }
    std::this_thread::sleep_for(200ms);
  }
  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 30s), 0) << read_file(log);
  ASSERT_FALSE(status.is_null()) << "no /status on the passed socket: " << read_file(log);
  EXPECT_GT(status["frames"]["out"].get<int>(), 0) << status.dump();
  const std::string out = read_file(log);
  EXPECT_NE(out.find("serving the socket systemd passed"), std::string::npos) << out;
  EXPECT_NE(out.find("serving http://127.0.0.1:" + std::to_string(port)), std::string::npos) << out;
}

TEST(SocketActivation, TwoSocketsAreAClearError) {
  int port_a = 0, port_b = 0;
  const int a = listening_socket(port_a);
  const int b = listening_socket(port_b);
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  const auto log = scratch_dir() / "two.log";
  const pid_t pid = start_activated({a, b}, {"--source", "sim:realtime=0"}, log);
  ::close(a);
  ::close(b);
  EXPECT_EQ(wait_exit(pid, 60s), 1);
  EXPECT_NE(read_file(log).find("systemd passed 2 sockets"), std::string::npos) << read_file(log);
}

}  // namespace
}  // namespace probeless::testing

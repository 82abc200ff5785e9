#include "app/service/systemd_notifier.hpp"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace probeless {
namespace {

// A stand-in for systemd's notify socket: an AF_UNIX datagram socket in a fresh temp dir
// (short path: sun_path holds 108 bytes), named in NOTIFY_SOCKET for the test's duration.
class FakeNotifySocket {
 public:
  FakeNotifySocket() {
    char dir_template[] = "/tmp/probeless-notify-XXXXXX";
    if (!mkdtemp(dir_template)) throw std::runtime_error("mkdtemp");
    dir_ = dir_template;
    path_ = dir_ + "/notify.sock";
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    path_.copy(addr.sun_path, sizeof addr.sun_path - 1);
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      throw std::runtime_error("bind " + path_);
    }
    setenv("NOTIFY_SOCKET", path_.c_str(), 1);
  }
  ~FakeNotifySocket() {
    unsetenv("NOTIFY_SOCKET");
    close(fd_);
    std::filesystem::remove_all(dir_);
  }

  // The next datagram, or "" after a second.
  std::string receive() {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, 1000) <= 0) return {};
    char buf[4096];
    const ssize_t n = recv(fd_, buf, sizeof buf, 0);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  }

 private:
  std::string dir_, path_;
  int fd_ = -1;
};

TEST(SystemdNotifier, SendsTheProtocolMessagesToNotifySocket) {
  FakeNotifySocket socket;
  SystemdNotifier notifier;
  EXPECT_TRUE(notifier.enabled());
  EXPECT_GT(notifier.ready(), 0);
  EXPECT_EQ(socket.receive(), "READY=1");
  EXPECT_GT(notifier.status("29.9 fps, sources streaming"), 0);
  EXPECT_EQ(socket.receive(), "STATUS=29.9 fps, sources streaming");
  EXPECT_GT(notifier.watchdog(), 0);
  EXPECT_EQ(socket.receive(), "WATCHDOG=1");
  EXPECT_GT(notifier.stopping(), 0);
  EXPECT_EQ(socket.receive(), "STOPPING=1");
}

TEST(SystemdNotifier, StatusIsOneLine) {
  FakeNotifySocket socket;
  SystemdNotifier notifier;
  notifier.status("rgbd: no signal\nREADY=1");  // must not smuggle a second assignment
  EXPECT_EQ(socket.receive(), "STATUS=rgbd: no signal READY=1");
}

TEST(SystemdNotifier, WithoutNotifySocketEverythingIsANoOp) {
  unsetenv("NOTIFY_SOCKET");
  SystemdNotifier notifier;
  EXPECT_FALSE(notifier.enabled());
  EXPECT_EQ(notifier.ready(), 0);
  EXPECT_EQ(notifier.status("x"), 0);
  EXPECT_EQ(notifier.watchdog(), 0);
  EXPECT_EQ(notifier.stopping(), 0);
}

TEST(SystemdNotifier, WatchdogIntervalFromTheEnvironment) {
  unsetenv("WATCHDOG_USEC");
  unsetenv("WATCHDOG_PID");
  EXPECT_FALSE(SystemdNotifier().watchdog_interval().has_value());

  setenv("WATCHDOG_USEC", "3000000", 1);
  setenv("WATCHDOG_PID", std::to_string(getpid()).c_str(), 1);
  const auto interval = SystemdNotifier().watchdog_interval();
  ASSERT_TRUE(interval.has_value());
  EXPECT_EQ(*interval, std::chrono::seconds(3));

  // Meant for another process (a child of the service, say): not ours to ping.
  setenv("WATCHDOG_PID", "1", 1);
  EXPECT_FALSE(SystemdNotifier().watchdog_interval().has_value());
  unsetenv("WATCHDOG_USEC");
  unsetenv("WATCHDOG_PID");
}

}  // namespace
}  // namespace probeless

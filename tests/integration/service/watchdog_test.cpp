// The watchdog covers every thread that matters (issue #20 item 6): with any one of the
// light, output (JPEG encoder), HTTP or RTSP threads wedged (`run --fault-hang THREAD:N`, a
// test-only fault: the thread blocks at its N-th heartbeat), WATCHDOG=1 stops while the
// process lives on, and /status names the stale thread; with none wedged the beats go on.
// The processing loop's case is Service.HungPipelineStopsTheWatchdog.
//
// Timing is generous on purpose: WATCHDOG_USEC = 4 s makes a heartbeat stale after 4 s and
// the beats come every 2 s, so silence is judged over 10 s windows, and no signal is
// declared only after 60 s without frames (a loaded machine renders the sim slowly).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "support/http_client.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless::testing {
namespace {

using namespace std::chrono_literals;
using loopback::http_get;

constexpr const char* kWatchdogUsec = "4000000";
constexpr auto kSilence = 10s;  // over two beat periods past the stale limit

std::string binary() {
  const char* b = std::getenv("PROBELESS_BINARY");
  return b ? b : "probeless";
}

class NotifySocket {
 public:
  NotifySocket() {
    char tmpl[] = "/tmp/probeless-notify-XXXXXX";  // sun_path holds 108 bytes
    if (!::mkdtemp(tmpl)) throw std::runtime_error("mkdtemp");
    dir_ = tmpl;
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", path().c_str());
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      throw std::runtime_error("bind " + path());
    timeval tv{0, 200000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~NotifySocket() {
    ::close(fd_);
    std::filesystem::remove_all(dir_);
  }
  std::string path() const { return (dir_ / "notify.sock").string(); }
  // WATCHDOG=1 datagrams received within `span`.
  int watchdog_beats_for(std::chrono::milliseconds span) {
    int beats = 0;
    const auto deadline = std::chrono::steady_clock::now() + span;
    while (std::chrono::steady_clock::now() < deadline) {
      char buf[4096];
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n > 0 &&
          std::string(buf, static_cast<std::size_t>(n)).find("WATCHDOG=1") != std::string::npos)
        ++beats;
    }
    return beats;
  }

 private:
  std::filesystem::path dir_;
  int fd_ = -1;
};

struct Service {
  NotifySocket socket;
  std::unique_ptr<Subprocess> proc;
  int port = -1;

  explicit Service(std::vector<std::string> extra) {
    const auto cfg = scratch_dir() / "watchdog.toml";
    std::FILE* f = std::fopen(cfg.c_str(), "w");
    std::fputs("[pipeline]\nno_signal_after_ms = 60000\n[rtsp]\nenabled = true\nport = 0\n", f);
    std::fclose(f);
    std::vector<std::string> argv{binary(), "run", "--port", "0", "--config", cfg.string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    proc = std::make_unique<Subprocess>(
        argv, std::map<std::string, std::string>{{"NOTIFY_SOCKET", socket.path()},
                                                 {"WATCHDOG_USEC", kWatchdogUsec}});
    const auto line = proc->wait_for_line("serving http://127.0.0.1:", 60s);
    std::smatch m;
    if (line && std::regex_search(*line, m, std::regex("127\\.0\\.0\\.1:([0-9]+)")))
      port = std::stoi(m[1]);
  }
  nlohmann::json status() const { return nlohmann::json::parse(http_get(port, "/status").body); }
  // Windows of kSilence until one has no beat; the beats counted before it.
  std::pair<int, bool> beats_until_silence(std::chrono::seconds deadline) {
    int beats = 0;
    const auto until = std::chrono::steady_clock::now() + deadline;
    while (std::chrono::steady_clock::now() < until) {
      const int in_window = socket.watchdog_beats_for(kSilence);
      if (beats > 0 && in_window == 0) return {beats, true};
      beats += in_window;
    }
    return {beats, false};
  }
  void stop_and_expect_clean_exit() {
    EXPECT_FALSE(proc->wait(0s).has_value()) << "the process must live on for systemd to kill";
    proc->send_signal(SIGTERM);
    const auto code = proc->wait(20s);
    ASSERT_TRUE(code.has_value()) << "a wedged thread kept the service from stopping";
    EXPECT_EQ(*code, 0) << proc->output();
  }
};

bool contains(const nlohmann::json& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

TEST(Watchdog, EveryThreadBeatsAndWatchdogGoesOn) {
  Service service({});
  ASSERT_GT(service.port, 0) << service.proc->output();
  // Beats in each of three windows, and every watched thread is listed and fresh.
  int windows_with_beats = 0;
  for (int i = 0; i < 3; ++i) windows_with_beats += service.socket.watchdog_beats_for(kSilence) > 0;
  EXPECT_EQ(windows_with_beats, 3);
  // Processing and light are watched from their first frame on (their OpenCL builds come
  // before): wait for them.
  nlohmann::json w;
  const auto until = std::chrono::steady_clock::now() + 120s;
  do {
    w = service.status()["watchdog"];
    if (w["threads"].size() == 5) break;
    std::this_thread::sleep_for(500ms);
  } while (std::chrono::steady_clock::now() < until);
  for (const char* thread : {"processing", "light", "output", "http", "rtsp"})
    EXPECT_TRUE(w["threads"].contains(thread)) << thread << " not watched: " << w.dump();
  EXPECT_EQ(w["stale_after_ms"], 4000);
  service.stop_and_expect_clean_exit();
}

class WedgedThread : public ::testing::TestWithParam<const char*> {};

TEST_P(WedgedThread, StopsTheWatchdogAndIsNamedInStatus) {
  const std::string thread = GetParam();
  // Each beats at least every 250 ms: 40 beats are a few seconds of healthy service first.
  Service service({"--fault-hang", thread + ":40"});
  ASSERT_GT(service.port, 0) << service.proc->output();
  const auto [beats, silent] = service.beats_until_silence(180s);
  EXPECT_GE(beats, 1) << "the watchdog beat before the fault";
  EXPECT_TRUE(silent) << "WATCHDOG=1 went on with the " << thread << " thread wedged";
  if (thread != "http") {  // with its loop wedged, HTTP cannot answer
    const nlohmann::json w = service.status()["watchdog"];
    EXPECT_TRUE(contains(w["stale"], thread)) << w.dump();
    EXPECT_EQ(w["stale"].size(), 1u) << "only the wedged thread is stale: " << w.dump();
  }
  service.stop_and_expect_clean_exit();
}

INSTANTIATE_TEST_SUITE_P(Threads, WedgedThread,
                         ::testing::Values("light", "output", "http", "rtsp"),
                         [](const auto& p) { return std::string(p.param); });

}  // namespace
}  // namespace probeless::testing

// The access rules of app/outputs/http_access.hpp as a client meets them over loopback, and
// the server's behaviour when it runs out of descriptors (issue #20).
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include "app/outputs/http_server.hpp"
#include "app/outputs/jpeg_encoder.hpp"
#include "http_test_client.hpp"
#include "test_images.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
using testing::http_exchange;
using testing::http_request;

HttpServerConfig ephemeral() {
  HttpServerConfig config;
  config.port = 0;
  return config;
}

std::string get(const std::string& target, const std::string& headers) {
  return "GET " + target + " HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n";
}

TEST(HttpServerAccess, AForeignHostIsRefusedBeforeAnyRoute) {
  HttpServer server(ephemeral());
  EXPECT_EQ(http_exchange(server.port(), get("/status", "Host: localhost:8080\r\n")).head.status,
            200);
  const auto rebound = http_exchange(server.port(), get("/status", "Host: evil.example\r\n"));
  EXPECT_EQ(rebound.head.status, 403);
  EXPECT_EQ(rebound.body.find("\"requests\""), std::string::npos) << "status leaked";
  EXPECT_EQ(http_exchange(server.port(), get("/snapshot", "Host: evil.example\r\n")).head.status,
            403);
  EXPECT_EQ(server.stats().refused, 2u);
}

TEST(HttpServerAccess, BasicAuthGuardsEveryRoute) {
  HttpServerConfig config = ephemeral();
  config.access.auth = HttpAuth::Basic;
  config.access.user = "viewer";
  config.access.password = "s3cret";
  HttpServer server(config);
  for (const char* target : {"/", "/status", "/snapshot", "/stream"}) {
    const auto r = http_request(server.port(), "GET", target);
    EXPECT_EQ(r.head.status, 401) << target;
    EXPECT_EQ(r.head.get("www-authenticate").rfind("Basic realm=", 0), 0u) << target;
  }
  const std::string good = "Host: localhost\r\nAuthorization: Basic dmlld2VyOnMzY3JldA==\r\n";
  EXPECT_EQ(http_exchange(server.port(), get("/status", good)).head.status, 200);
  EXPECT_EQ(http_exchange(server.port(), get("/", good)).head.status, 200);
  const std::string wrong = "Host: localhost\r\nAuthorization: Basic dmlld2VyOnMzY3Jl\r\n";
  EXPECT_EQ(http_exchange(server.port(), get("/status", wrong)).head.status, 401);
}

TEST(HttpServerAccess, CorsOriginIsAnnouncedAndPreflightAnswered) {
  HttpServerConfig config = ephemeral();
  HttpServer plain(config);
  EXPECT_EQ(http_request(plain.port(), "GET", "/status").head.get("access-control-allow-origin"),
            "");
  config.access.cors_origin = "https://dash.local";
  HttpServer server(config);
  EXPECT_EQ(http_request(server.port(), "GET", "/status").head.get("access-control-allow-origin"),
            "https://dash.local");
  const auto preflight = http_request(server.port(), "OPTIONS", "/status");
  // 200 as ustreamer answers OPTIONS (it was 204 before issue #22); either passes a preflight.
  EXPECT_EQ(preflight.head.status, 200);
  EXPECT_EQ(preflight.head.get("access-control-allow-methods"), "GET, HEAD, OPTIONS");
  EXPECT_EQ(preflight.head.get("access-control-allow-origin"), "https://dash.local");
}

// The first IPv4 address of this machine that is not loopback, if it has one.
std::string non_loopback_address() {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return {};
  std::string found;
  for (ifaddrs* a = list; a && found.empty(); a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
    char text[INET_ADDRSTRLEN];
    inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof text);
    if (!is_loopback_address(text)) found = text;
  }
  freeifaddrs(list);
  return found;
}

TEST(HttpServerAccess, OneAddressCannotTakeEveryStreamSlot) {
  const std::string address = non_loopback_address();
  if (address.empty()) GTEST_SKIP() << "no non-loopback IPv4 address to connect from";
  HttpServerConfig config = ephemeral();
  config.address = address;
  config.access.allowed_hosts = {"*"};
  config.access.max_streams_per_peer = 2;
  HttpServer server(config);
  server.publish({JpegEncoder(80).encode_shared(testing::gradient_image(64, 48)), 1});
  // TcpClient connects to 127.0.0.1; this server listens elsewhere, so connect by hand.
  auto open_stream = [&] {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(server.port()));
    inet_pton(AF_INET, address.c_str(), &to.sin_addr);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to), 0);
    const std::string req = "GET /stream HTTP/1.1\r\nHost: x\r\n\r\n";
    EXPECT_EQ(::send(fd, req.data(), req.size(), MSG_NOSIGNAL), static_cast<ssize_t>(req.size()));
    return fd;
  };
  auto status_of = [](int fd) {
    std::string head;
    char buf[512];
    pollfd p{fd, POLLIN, 0};
    while (head.find("\r\n") == std::string::npos && ::poll(&p, 1, 5000) > 0) {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      head.append(buf, static_cast<std::size_t>(n));
    }
    return head.size() > 12 ? std::stoi(head.substr(9, 3)) : 0;
  };
  const int a = open_stream(), b = open_stream(), c = open_stream();
  EXPECT_EQ(status_of(a), 200);
  EXPECT_EQ(status_of(b), 200);
  EXPECT_EQ(status_of(c), 429);
  for (int fd : {a, b, c}) ::close(fd);
}

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

// libevent 2.1 retries a failed accept() at once, forever: out of descriptors, the server
// thread would burn a core and flood the log. It must pause, and serve again once
// descriptors are free.
TEST(HttpServerAccess, OutOfDescriptorsTheServerPausesInsteadOfSpinningAndRecovers) {
  HttpServer server(ephemeral());
  const int port = server.port();
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &saved), 0);
  // A child connects while this process has no descriptor to accept with.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::usleep(100'000);
    int fds[4];
    for (int& fd : fds) {
      fd = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in to{};
      to.sin_family = AF_INET;
      to.sin_port = htons(static_cast<uint16_t>(port));
      to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      (void)::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to);
    }
    ::usleep(1'500'000);
    _exit(0);
  }
  rlimit tight = saved;
  tight.rlim_cur = 3;  // stdin, stdout, stderr: nothing more can be opened
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &tight), 0);
  std::this_thread::sleep_for(200ms);  // the child's connections are pending
  const double cpu0 = cpu_seconds();
  std::this_thread::sleep_for(800ms);
  const double cpu = cpu_seconds() - cpu0;
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &saved), 0);
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_GE(server.stats().accept_failures, 1u);
  EXPECT_LT(cpu, 0.15) << "the server spun on accept() for " << cpu << " s of CPU in 0.8 s";
  std::this_thread::sleep_for(300ms);  // past the pause
  EXPECT_EQ(http_request(port, "GET", "/status").head.status, 200);
}

}  // namespace
}  // namespace probeless

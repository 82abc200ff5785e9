#include "app/service/socket_activation.hpp"

#include <netdb.h>
#include <sys/socket.h>
#include <systemd/sd-daemon.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace probeless {

int http_socket_from_systemd() {
  const int n = sd_listen_fds(1);
  if (n < 0) {
    throw std::runtime_error(std::string("socket activation: sd_listen_fds: ") + std::strerror(-n));
  }
  if (n == 0) return -1;
  if (n > 1) {
    throw std::runtime_error("socket activation: systemd passed " + std::to_string(n) +
                             " sockets, the service serves one (probeless.socket: one "
                             "ListenStream=)");
  }
  const int fd = SD_LISTEN_FDS_START;
  if (sd_is_socket(fd, AF_UNSPEC, SOCK_STREAM, 1) <= 0) {
    throw std::runtime_error(
        "socket activation: the socket systemd passed is not a listening stream socket "
        "(probeless.socket needs ListenStream= and Accept=no)");
  }
  return fd;
}

std::string bound_address(int fd) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return {};
  char host[NI_MAXHOST];
  if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, nullptr, 0,
                  NI_NUMERICHOST) != 0)
    return {};
  return host;
}

}  // namespace probeless

#pragma once
// systemd socket activation (sd_listen_fds(3)) for the HTTP listener: probeless.socket
// (systemd/, docs/appliance.md "Socket activation") binds the viewer's port before the
// service starts and keeps it across restarts, and can bind a port below 1024 for a service
// that has no capabilities at all.

#include <string>

namespace probeless {

// The listening socket systemd passed (SD_LISTEN_FDS_START), or -1 when the process was
// started without one (from a shell, by the unit without probeless.socket). Unsets
// LISTEN_FDS/LISTEN_PID so no child inherits them. Throws std::runtime_error naming what
// is wrong when systemd passed something the service cannot serve: more than one socket,
// or one that is not a listening stream socket (ListenDatagram=, Accept=yes).
int http_socket_from_systemd();

// The numeric address a listening socket is bound to ("127.0.0.1", "::"), for the URL the
// service prints; "" when it cannot be read.
std::string bound_address(int fd);

}  // namespace probeless

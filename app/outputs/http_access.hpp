#pragma once
// Who may talk to the HTTP server (issue #20 item 4), decided per request before any route
// runs. Kept apart from libevent so every rule is tested on plain strings.
//
// - Host check against DNS rebinding: a page on a hostile site whose name resolves to the
//   appliance's address would otherwise read /snapshot through the visitor's browser. A
//   browser always sends the name it resolved in `Host`, so the server answers only to names
//   it knows: `allowed_hosts`, or, when that is empty and the server listens on loopback,
//   the loopback names. A request without Host (HTTP/1.0 tools) is not a browser's and passes.
// - Authentication, optional: HTTP basic (what a browser prompts for, so the viewer page and
//   <img src="/stream"> keep working) or a bearer token (scripts). Compared in constant time.
// - CORS: an origin allowed to read the server's responses from scripts (none by default, so
//   other sites' scripts cannot read /status even with the Host check passed).
#include <string>
#include <string_view>
#include <vector>

namespace probeless {

enum class HttpAuth { None, Basic, Bearer };

// [http] keys of the service config (docs/configuration.md).
struct HttpAccessConfig {
  std::vector<std::string> allowed_hosts;  // names or literals, without port; "*" = any
  HttpAuth auth = HttpAuth::None;
  std::string user, password;    // basic
  std::string token;             // bearer
  std::string cors_origin;       // e.g. "https://dashboard.local"; empty: no CORS headers
  int max_streams_per_peer = 4;  // streams one address may hold: one viewer cannot take all
};

enum class AccessDecision { Allow, BadHost, Unauthorised };

// `bind_address` is the address the server listens on ("127.0.0.1", "0.0.0.0", "::1", ...);
// `host` and `authorization` are the request's headers, null when absent.
AccessDecision check_access(const HttpAccessConfig& config, std::string_view bind_address,
                            const char* host, const char* authorization);

// The host part of a Host header: "[::1]:8080" -> "::1", "Box.local:80" -> "box.local".
std::string host_name_of(std::string_view host_header);

bool is_loopback_address(std::string_view address);

// The WWW-Authenticate value for a 401, empty when auth is off.
std::string authenticate_challenge(const HttpAccessConfig& config);

// Parses "none" | "basic" | "bearer"; throws std::invalid_argument naming the value.
HttpAuth parse_http_auth(std::string_view text);

}  // namespace probeless

#include "app/outputs/http_access.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <stdexcept>

namespace probeless {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// Equal without an early exit, so response time does not tell how much of a guess was right.
bool constant_time_equal(std::string_view a, std::string_view b) {
  const std::size_t n = std::max(a.size(), b.size());
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned ca = i < a.size() ? static_cast<unsigned char>(a[i]) : 0u;
    const unsigned cb = i < b.size() ? static_cast<unsigned char>(b[i]) : 0u;
    diff |= ca ^ cb;
  }
  return diff == 0;
}

// RFC 4648 base64, strict: anything else than the alphabet and trailing '=' fails.
bool base64_decode(std::string_view in, std::string& out) {
  if (in.size() % 4 != 0 || in.size() > 4096) return false;
  std::array<int, 256> value{};
  value.fill(-1);
  const std::string_view alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (std::size_t i = 0; i < alphabet.size(); ++i)
    value[static_cast<unsigned char>(alphabet[i])] = static_cast<int>(i);
  out.clear();
  for (std::size_t i = 0; i < in.size(); i += 4) {
    int v[4];
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = in[i + k];
      if (c == '=' && i + 4 == in.size() && k >= 2) {
        v[k] = 0;
        ++pad;
        continue;
      }
      if (pad > 0) return false;
      v[k] = value[static_cast<unsigned char>(c)];
      if (v[k] < 0) return false;
    }
    const unsigned triple = static_cast<unsigned>(v[0] << 18 | v[1] << 12 | v[2] << 6 | v[3]);
    out.push_back(static_cast<char>(triple >> 16 & 0xff));
    if (pad < 2) out.push_back(static_cast<char>(triple >> 8 & 0xff));
    if (pad < 1) out.push_back(static_cast<char>(triple & 0xff));
  }
  return true;
}

bool has_scheme(std::string_view header, std::string_view scheme, std::string_view& credentials) {
  if (header.size() <= scheme.size() || lower(header.substr(0, scheme.size())) != scheme ||
      header[scheme.size()] != ' ')
    return false;
  credentials = header.substr(scheme.size() + 1);
  while (!credentials.empty() && credentials.front() == ' ') credentials.remove_prefix(1);
  return true;
}

bool authorised(const HttpAccessConfig& config, const char* authorization) {
  if (config.auth == HttpAuth::None) return true;
  if (authorization == nullptr) return false;
  std::string_view credentials;
  if (config.auth == HttpAuth::Bearer) {
    return has_scheme(authorization, "bearer", credentials) &&
           constant_time_equal(credentials, config.token);
  }
  std::string decoded;
  if (!has_scheme(authorization, "basic", credentials) || !base64_decode(credentials, decoded))
    return false;
  return constant_time_equal(decoded, config.user + ":" + config.password);
}

bool host_allowed(const HttpAccessConfig& config, std::string_view bind_address, const char* host) {
  if (host == nullptr) return true;
  const std::string name = host_name_of(host);
  if (config.allowed_hosts.empty()) {
    if (!is_loopback_address(bind_address)) return true;
    return name == "localhost" || is_loopback_address(name);
  }
  return std::any_of(
      config.allowed_hosts.begin(), config.allowed_hosts.end(),
      [&](const std::string& allowed) { return allowed == "*" || lower(allowed) == name; });
}

}  // namespace

std::string host_name_of(std::string_view host_header) {
  if (!host_header.empty() && host_header.front() == '[') {
    const auto close = host_header.find(']');
    return lower(host_header.substr(
        1, close == std::string_view::npos ? std::string_view::npos : close - 1));
  }
  const auto colon = host_header.find(':');
  // More than one colon and no brackets: a bare IPv6 literal, which has no port.
  if (colon != std::string_view::npos && host_header.find(':', colon + 1) == std::string_view::npos)
    host_header = host_header.substr(0, colon);
  std::string name = lower(host_header);
  if (!name.empty() && name.back() == '.') name.pop_back();  // "localhost." is localhost
  return name;
}

bool is_loopback_address(std::string_view address) {
  return address == "::1" || address.starts_with("127.");
}

AccessDecision check_access(const HttpAccessConfig& config, std::string_view bind_address,
                            const char* host, const char* authorization) {
  if (!host_allowed(config, bind_address, host)) return AccessDecision::BadHost;
  if (!authorised(config, authorization)) return AccessDecision::Unauthorised;
  return AccessDecision::Allow;
}

std::string authenticate_challenge(const HttpAccessConfig& config) {
  switch (config.auth) {
    case HttpAuth::Basic:
      return "Basic realm=\"probeless\", charset=\"UTF-8\"";
    case HttpAuth::Bearer:
      return "Bearer realm=\"probeless\"";
    case HttpAuth::None:
      break;
  }
  return {};
}

HttpAuth parse_http_auth(std::string_view text) {
  if (text == "none") return HttpAuth::None;
  if (text == "basic") return HttpAuth::Basic;
  if (text == "bearer") return HttpAuth::Bearer;
  throw std::invalid_argument("auth must be \"none\", \"basic\" or \"bearer\", not \"" +
                              std::string(text) + "\"");
}

}  // namespace probeless

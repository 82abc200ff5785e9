#include "app/outputs/display/display_mode.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace probeless::display {
namespace {

bool parse_int(std::string_view s, int& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && out > 0;
}

bool iequals(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  });
}

std::string offered(std::span<const ModeInfo> modes) {
  std::string list;
  for (const auto& m : modes)
    list += (list.empty() ? "" : ", ") + to_string(m) + (m.preferred ? " (preferred)" : "");
  return list.empty() ? "no modes" : list;
}

}  // namespace

ModeRequest parse_mode_request(std::string_view text) {
  const auto bad = [&] {
    return DisplayError(fmt::format(
        "display mode \"{}\": expected WIDTHxHEIGHT or WIDTHxHEIGHT@HZ (e.g. 1920x1080@60)", text));
  };
  ModeRequest r;
  const auto x = text.find('x');
  if (x == std::string_view::npos) throw bad();
  const auto at = text.find('@', x);
  if (!parse_int(text.substr(0, x), r.width)) throw bad();
  if (!parse_int(text.substr(x + 1, at == std::string_view::npos ? text.npos : at - x - 1),
                 r.height))
    throw bad();
  if (at != std::string_view::npos) {
    // std::from_chars for double is in GCC 12's libstdc++, but strtod is the one that also
    // builds on older cross toolchains; the text is copied to be NUL-terminated.
    const std::string hz(text.substr(at + 1));
    char* end = nullptr;
    const double v = std::strtod(hz.c_str(), &end);
    if (hz.empty() || end != hz.c_str() + hz.size() || !(v > 0 && v < 1000)) throw bad();
    r.refresh_hz = v;
  }
  if (r.width > 16384 || r.height > 16384) throw bad();
  return r;
}

std::string to_string(const ModeRequest& r) {
  return r.refresh_hz ? fmt::format("{}x{}@{:g}", r.width, r.height, *r.refresh_hz)
                      : fmt::format("{}x{}", r.width, r.height);
}

std::string to_string(const ModeInfo& m) {
  return fmt::format("{}x{}@{:.2f}", m.width, m.height, m.refresh_hz);
}

std::size_t choose_mode(std::span<const ModeInfo> modes, const std::optional<ModeRequest>& request,
                        std::string_view connector_name) {
  if (modes.empty()) throw DisplayError(fmt::format("{} offers no modes", connector_name));
  if (!request) {
    for (std::size_t i = 0; i < modes.size(); ++i)
      if (modes[i].preferred) return i;
    return 0;
  }
  std::optional<std::size_t> best;
  const auto better = [&](std::size_t i) {
    if (!best) return true;
    const ModeInfo &m = modes[i], &b = modes[*best];
    // With a rate asked: the closest (59.94 and 60 are both listed on most HDMI sinks).
    if (request->refresh_hz)
      return std::abs(m.refresh_hz - *request->refresh_hz) <
             std::abs(b.refresh_hz - *request->refresh_hz);
    // Without: the preferred mode of that size, else its fastest.
    if (m.preferred != b.preferred) return m.preferred;
    return m.refresh_hz > b.refresh_hz;
  };
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const ModeInfo& m = modes[i];
    if (m.width != request->width || m.height != request->height) continue;
    if (request->refresh_hz && std::abs(m.refresh_hz - *request->refresh_hz) > 0.5) continue;
    if (better(i)) best = i;
  }
  if (best) return *best;
  throw DisplayError(fmt::format("mode {} is not offered by {} (it offers {})", to_string(*request),
                                 connector_name, offered(modes)));
}

std::filesystem::path card_path(const std::string& card, const std::filesystem::path& dri_dir) {
  if (card.find('/') != std::string::npos) return card;
  return dri_dir / card;
}

std::size_t choose_connector(std::span<const ConnectorInfo> connectors, std::string_view name,
                             std::string_view card) {
  std::string listed;
  for (const auto& c : connectors)
    listed += fmt::format("{}{} ({})", listed.empty() ? "" : ", ", c.name,
                          c.connected ? "connected" : "disconnected");
  if (listed.empty()) listed = "none";
  for (std::size_t i = 0; i < connectors.size(); ++i) {
    if (name.empty() ? !connectors[i].connected : !iequals(connectors[i].name, name)) continue;
    if (!connectors[i].connected)
      throw DisplayError(
          fmt::format("connector {} on {} is not connected (nothing plugged in, "
                      "or the sink gives no EDID)",
                      connectors[i].name, card));
    return i;
  }
  if (!name.empty())
    throw DisplayError(fmt::format("no connector named {} on {} (it has: {})", name, card, listed));
  throw DisplayError(fmt::format("no connected connector on {} (it has: {})", card, listed));
}

Viewport letterbox(int image_width, int image_height, int screen_width, int screen_height) {
  if (image_width <= 0 || image_height <= 0 || screen_width <= 0 || screen_height <= 0)
    return {0, 0, std::max(screen_width, 0), std::max(screen_height, 0)};
  // Compare cross products in 64 bits: which axis limits the scale, without rounding.
  const auto iw = static_cast<std::int64_t>(image_width),
             ih = static_cast<std::int64_t>(image_height);
  Viewport v;
  if (iw * screen_height >= ih * screen_width) {  // wider than the screen: bars top and bottom
    v.width = screen_width;
    v.height = static_cast<int>((ih * screen_width + iw / 2) / iw);
  } else {  // taller: bars left and right
    v.height = screen_height;
    v.width = static_cast<int>((iw * screen_height + ih / 2) / ih);
  }
  v.x = (screen_width - v.width) / 2;
  v.y = (screen_height - v.height) / 2;
  return v;
}

}  // namespace probeless::display

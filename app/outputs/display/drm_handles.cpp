#include "app/outputs/display/drm_handles.hpp"

#include <fcntl.h>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

namespace probeless::display {

std::vector<std::filesystem::path> list_cards(const std::filesystem::path& dri_dir) {
  std::vector<std::pair<int, std::filesystem::path>> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dri_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= 4 || name.compare(0, 4, "card") != 0) continue;
    if (!std::all_of(name.begin() + 4, name.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    found.emplace_back(std::stoi(name.substr(4)), entry.path());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::filesystem::path> cards;
  for (auto& [n, path] : found) cards.push_back(std::move(path));
  return cards;
}

UniqueFd open_card(const std::filesystem::path& path) {
  UniqueFd fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
  if (fd) return fd;
  const int err = errno;
  if (err == ENOENT)
    throw DisplayError(fmt::format("no DRM device {} (no KMS driver bound to it)", path.string()));
  if (err == EACCES || err == EPERM)
    throw DisplayError(
        fmt::format("{}: permission denied (the service user needs the video "
                    "group, or DeviceAllow= in the unit)",
                    path.string()));
  throw DisplayError(fmt::format("{}: cannot open: {}", path.string(), std::strerror(err)));
}

ModeResources get_resources(const UniqueFd& fd, const std::filesystem::path& path) {
  ModeResources res(drmModeGetResources(fd.get()));
  if (!res) {
    const int err = errno;
    throw DisplayError(fmt::format("{} is not a KMS display device (drmModeGetResources: {})",
                                   path.string(), std::strerror(err)));
  }
  return res;
}

std::string connector_name(const drmModeConnector& c) {
  const char* type = drmModeGetConnectorTypeName(c.connector_type);
  return fmt::format("{}-{}", type != nullptr ? type : "Unknown", c.connector_type_id);
}

ModeInfo mode_info(const drmModeModeInfo& m) {
  ModeInfo info;
  info.width = m.hdisplay;
  info.height = m.vdisplay;
  // vrefresh is rounded to whole Hz; the clock (kHz) over the totals gives 59.94 exactly.
  double hz = m.vrefresh;
  if (m.htotal > 0 && m.vtotal > 0) {
    hz = m.clock * 1000.0 / (static_cast<double>(m.htotal) * m.vtotal);
    if (m.flags & DRM_MODE_FLAG_INTERLACE) hz *= 2;
    if (m.flags & DRM_MODE_FLAG_DBLSCAN) hz /= 2;
    if (m.vscan > 1) hz /= m.vscan;
  }
  info.refresh_hz = hz;
  info.preferred = (m.type & DRM_MODE_TYPE_PREFERRED) != 0;
  return info;
}

std::string driver_name(const UniqueFd& fd) {
  drmVersionPtr v = drmGetVersion(fd.get());
  if (v == nullptr) return "?";
  std::string name(v->name, static_cast<std::size_t>(v->name_len));
  drmFreeVersion(v);
  return name;
}

}  // namespace probeless::display

#include "app/outputs/display/drm_inventory.hpp"

#include "app/outputs/display/drm_handles.hpp"

namespace probeless::display {

std::vector<CardInventory> list_displays(const std::filesystem::path& dri_dir) {
  std::vector<CardInventory> cards;
  for (const auto& path : list_cards(dri_dir)) {
    CardInventory card;
    card.path = path;
    try {
      const UniqueFd fd = open_card(path);
      card.driver = driver_name(fd);
      const ModeResources res = get_resources(fd, path);
      for (int i = 0; i < res->count_connectors; ++i) {
        // drmModeGetConnector probes the connector (reads the EDID): what is plugged in now.
        ModeConnector c(drmModeGetConnector(fd.get(), res->connectors[i]));
        if (!c) continue;
        ConnectorInventory conn;
        conn.info = {connector_name(*c), c->connection == DRM_MODE_CONNECTED};
        conn.width_mm = static_cast<int>(c->mmWidth);
        conn.height_mm = static_cast<int>(c->mmHeight);
        for (int m = 0; m < c->count_modes; ++m) conn.modes.push_back(mode_info(c->modes[m]));
        card.connectors.push_back(std::move(conn));
      }
    } catch (const DisplayError& e) {
      card.error = e.what();
    }
    cards.push_back(std::move(card));
  }
  return cards;
}

}  // namespace probeless::display

#pragma once
// The device-free half of the tethered display (docs/display.md): the config's mode string,
// the choice of connector and mode among what a card offers, and the letterbox that fits the
// composite into the mode. No DRM headers here, so the rules are unit-tested on any machine.
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace probeless::display {

// Why the display cannot show anything: no card, no connector, no mode, a busy device, a
// failed flip. The message is meant for the log and /status as it is.
class DisplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "1920x1080", "1920x1080@60" or "1280x720@59.94" ([display] mode).
struct ModeRequest {
  int width = 0;
  int height = 0;
  std::optional<double> refresh_hz;  // none: the best rate offered at that size
};

// Throws DisplayError naming the text and the expected form.
ModeRequest parse_mode_request(std::string_view text);
std::string to_string(const ModeRequest& request);

// One mode as a connector offers it (a drmModeModeInfo without the timings).
struct ModeInfo {
  int width = 0;
  int height = 0;
  double refresh_hz = 0;  // from the pixel clock and totals, so 59.94 is not rounded to 60
  bool preferred = false;
};
std::string to_string(const ModeInfo& mode);  // "1024x768@60.00"

// The mode to set: the request's size (and the closest rate within 0.5 Hz when it gives one;
// without a rate the preferred mode of that size, else its fastest), or with no request the
// preferred mode, else the first listed (the kernel lists the best first). Throws
// DisplayError listing what the connector offers when nothing matches.
std::size_t choose_mode(std::span<const ModeInfo> modes, const std::optional<ModeRequest>& request,
                        std::string_view connector_name);

struct ConnectorInfo {
  std::string name;  // "HDMI-A-1", "Virtual-1": the kernel's type name and per-type index
  bool connected = false;
};

// [display] card: "card0" -> dri_dir/card0; a path with a '/' is used as it is.
std::filesystem::path card_path(const std::string& card, const std::filesystem::path& dri_dir);

// The connector named (case-insensitive), which must be connected, or the first connected one.
std::size_t choose_connector(std::span<const ConnectorInfo> connectors, std::string_view name,
                             std::string_view card);

// Where the image goes on the screen: the largest rectangle of the image's aspect ratio
// centred in the screen, black bars on the other axis.
struct Viewport {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool operator==(const Viewport&) const = default;
};
Viewport letterbox(int image_width, int image_height, int screen_width, int screen_height);

}  // namespace probeless::display

#include "app/cli/devices_libcamera.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#ifdef PROBELESS_HAVE_LIBCAMERA
#include "drivers/libcamera/libcamera_runtime.hpp"
#endif

namespace probeless::cli {
namespace {

#ifdef PROBELESS_HAVE_LIBCAMERA
// A control the bracket cycle needs: offered, or what the source does without it.
std::string bracket_control(bool offered) {
  return offered ? "per request"
                 : "NOT OFFERED: the bracket's value is not applied, frames keep it";
}

// "label a, b, c" wrapped at ~90 columns (a camera has dozens of controls).
void print_wrapped(std::ostream& out, const char* label, const std::vector<std::string>& items) {
  const std::string indent(std::string_view(label).size(), ' ');
  std::string line;
  const char* first = label;
  for (const auto& item : items) {
    if (!line.empty() && line.size() + item.size() > 76) {
      out << first << line << ",\n";
      first = indent.c_str();
      line.clear();
    }
    if (!line.empty()) line += ", ";
    line += item;
  }
  out << first << (line.empty() ? "none" : line) << '\n';
}
#endif

}  // namespace

void print_libcamera_cameras(std::ostream& out) {
  out << "libcamera cameras\n";
#ifdef PROBELESS_HAVE_LIBCAMERA
  std::vector<libcam::CameraDescription> cameras;
  try {
    cameras = libcam::list_libcamera_cameras();
  } catch (const std::exception& e) {
    out << "  libcamera did not start: " << e.what() << '\n';
    return;
  }
  if (cameras.empty())
    out << "  no camera: libcamera found none (a CSI sensor with its pipeline handler, a UVC "
           "camera, or vimc in the VM tests)\n";
  for (const auto& c : cameras) {
    out << fmt::format("  '{}'{}\n", c.id, c.model.empty() ? "" : " (" + c.model + ")");
    out << "      ExposureTime: " << bracket_control(c.exposure_time) << '\n';
    out << "      AnalogueGain: " << bracket_control(c.analogue_gain) << '\n';
    print_wrapped(out, "      controls: ", c.controls);
    print_wrapped(out, "      formats: ", c.formats);
  }
#else
  out << "  not built: libcamera-dev was not found when this build was configured\n";
#endif
}

}  // namespace probeless::cli

#include "app/cli/devices_board.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "drivers/openni2/openni2_options.hpp"
#include "drivers/openni2/openni2_runtime.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/trigger/gpio_chips.hpp"
#include "drivers/usb/usb_hotplug.hpp"
#include "drivers/v4l2/v4l2_options.hpp"

namespace probeless::cli {
namespace {

namespace fs = std::filesystem;

// "" when this user may read and write `path`, else why not (the errno text), with the fix
// for the usual cause.
std::string access_problem(const std::string& path, const char* group) {
  if (::access(path.c_str(), F_OK) != 0) return std::strerror(errno);
  if (::access(path.c_str(), R_OK | W_OK) == 0) return {};
  return fmt::format(
      "{} (permission: add the user to group '{}', as the package does for the "
      "probeless service user)",
      std::strerror(errno), group);
}

// RGBD_SPEC+FISHEYE_SPEC with the fisheye's calibration=FILE taken out.
struct SpecParts {
  std::string rgbd, fisheye, calibration;
};
SpecParts split(const std::string& spec) {
  SpecParts p;
  const auto plus = spec.find('+');
  p.rgbd = spec.substr(0, plus);
  if (plus == std::string::npos) return p;
  p.fisheye = spec.substr(plus + 1);
  const auto at = p.fisheye.find("calibration=");
  if (at != std::string::npos) {
    const auto end = p.fisheye.find_first_of("&,", at);
    p.calibration = p.fisheye.substr(at + 12, end == std::string::npos ? end : end - at - 12);
    std::size_t from =
        at > 0 && (p.fisheye[at - 1] == '&' || p.fisheye[at - 1] == ',') ? at - 1 : at;
    p.fisheye.erase(from, end == std::string::npos ? std::string::npos : end - from);
    if (p.fisheye.ends_with('?')) p.fisheye.pop_back();
  }
  return p;
}

void check_rgbd(const std::string& spec, std::vector<Need>& needs) {
  if (!spec.starts_with("openni2:")) return;
  const auto options = openni2::parse_openni2_options(spec.substr(8));
  Need n{"RGB-D sensor (OpenNI2)", false, {}};
  try {
    const auto devices = openni2::list_openni_devices();
    if (!devices.empty()) {
      n.ok = true;
      n.detail = fmt::format("{} '{}'", devices.front().uri, devices.front().name);
    }
  } catch (const openni2::OpenniError& e) {
    n.detail = e.what();
  }
  if (!n.ok) {
    try {
      const auto usb = usb::list_usb_devices(options.usb_vendors);
      n.detail = usb.empty()
                     ? "none plugged in (no USB device of the sensor vendors; plug it into a "
                       "USB 3 port)"
                     : fmt::format(
                           "{} is on USB but OpenNI2 cannot open it: permission (the "
                           "udev rule 60-probeless.rules, then replug) or its driver",
                           usb::describe(usb.front()));
    } catch (const usb::UsbError& e) {
      n.detail += (n.detail.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  needs.push_back(n);
}

// The fisheye device, and the calibration against its size. Returns the size asked for.
void check_fisheye(const std::string& spec, std::vector<Need>& needs, int& width, int& height) {
  if (!spec.starts_with("v4l2:")) return;
  const auto options = v4l2::parse_v4l2_options(spec.substr(5));
  width = options.width;
  height = options.height;
  Need n{"fisheye " + options.device, false, {}};
  if (!options.device.starts_with('/')) {
    // A card name: the source finds it among /dev/video*.
    for (const auto& e :
         fs::directory_iterator("/dev", fs::directory_options::skip_permission_denied))
      if (e.path().filename().string().starts_with("video")) n.ok = true;
    n.detail = n.ok ? "card name: looked up among /dev/video* when the service starts"
                    : "no /dev/video* at all: plug the camera in";
  } else {
    const std::string problem = access_problem(options.device, "video");
    n.ok = problem.empty();
    n.detail = n.ok ? "present, readable and writable" : problem;
  }
  needs.push_back(n);
}

void check_calibration(const std::string& file, int width, int height, std::vector<Need>& needs) {
  Need n{"calibration " + file, false, {}};
  if (!fs::exists(file)) {
    n.detail =
        "no such file: record a calibration sequence and run `probeless calibrate` "
        "(docs/bring-up.md, docs/calibration.md)";
  } else {
    try {
      const RigCalibration c = replay::load_rig_calibration(file);
      n.ok = true;
      n.detail = fmt::format("colour {} x {}", c.rgb.width(), c.rgb.height());
      if (c.fisheye) {
        n.detail += fmt::format(", fisheye {} {} x {}", c.fisheye->kind(), c.fisheye->width(),
                                c.fisheye->height());
        if (width > 0 && (c.fisheye->width() != width || c.fisheye->height() != height)) {
          n.ok = false;
          n.detail += fmt::format(", but the source asks the fisheye for {} x {}", width, height);
        }
      } else {
        n.ok = false;
        n.detail += ", no fisheye: light capture needs one";
      }
    } catch (const std::exception& e) {
      n.detail = e.what();
    }
  }
  needs.push_back(n);
}

void check_gpio(const std::string& role, const std::string& chip, std::vector<Need>& needs) {
  if (chip.empty()) return;
  Need n{role + " GPIO chip '" + chip + "'", false, "no gpiochip with that name or label"};
  for (const auto& c : list_gpio_chips()) {
    if (c.name != chip && c.label != chip && c.path != chip) continue;
    n.ok = c.error.empty();
    n.detail = n.ok ? c.path : c.path + ": " + c.error + " (permission: group 'gpio')";
    break;
  }
  needs.push_back(n);
}

void check_display(const ServiceConfig& config, std::vector<Need>& needs) {
  if (!config.display.enabled) return;
  Need n{"display (DRM/KMS)", false, "no /dev/dri/card*: no KMS display driver is loaded"};
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/dev/dri", ec)) {
    if (!e.path().filename().string().starts_with("card")) continue;
    const std::string problem = access_problem(e.path().string(), "video");
    n.ok = problem.empty();
    n.detail = e.path().string() + (n.ok ? "" : ": " + problem);
    if (n.ok) break;
  }
  needs.push_back(n);
}

}  // namespace

std::vector<Need> check_needs(const ServiceConfig& config) {
  std::vector<Need> needs;
  if (config.source == "sim" || config.source.starts_with("sim:")) {
    needs.push_back({"source: the synthetic rig", true, "needs no device"});
  } else {
    const SpecParts parts = split(config.source);
    int width = 0, height = 0;
    check_rgbd(parts.rgbd, needs);
    check_fisheye(parts.fisheye, needs, width, height);
    if (!parts.fisheye.empty() && parts.calibration.empty())
      needs.push_back({"calibration", false,
                       "the source names none (add &calibration=FILE to the fisheye spec)"});
    if (!parts.calibration.empty()) check_calibration(parts.calibration, width, height, needs);
  }
  check_gpio("trigger", config.trigger_chip, needs);
  check_gpio("strobe", config.strobe_chip, needs);
  check_display(config, needs);
  return needs;
}

void print_needs(std::ostream& out, const ServiceConfig& config) {
  out << "What this config needs"
      << (config.board.empty() ? std::string()
                               : " (board " + config.about_name + ", " + config.board + ")")
      << "\n";
  out << fmt::format("  source: {}\n", config.source);
  int missing = 0;
  for (const Need& n : check_needs(config)) {
    out << fmt::format("  {:8} {}: {}\n", n.ok ? "ok" : "MISSING", n.what, n.detail);
    missing += n.ok ? 0 : 1;
  }
  out << (missing == 0 ? std::string("  nothing missing\n")
                       : fmt::format("  {} missing: `probeless run` would not get its picture "
                                     "until they are there\n",
                                     missing));
}

}  // namespace probeless::cli

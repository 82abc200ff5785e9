// probeless devices: what this machine offers the service, one section per kind of device.
// OpenCL (platforms, devices, and the one the selector picks), GPIO chips and DRM/KMS
// displays; cameras are further sections of the same list.
#include <fmt/format.h>

#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli/commands.hpp"
#include "app/cli/devices_board.hpp"
#include "app/cli/devices_libcamera.hpp"
#include "app/cli/devices_rgbd.hpp"
#include "app/outputs/display/drm_inventory.hpp"
#include "app/pipeline/service_config.hpp"
#include "drivers/openni2/openni2_options.hpp"
#include "drivers/trigger/gpio_chips.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_list.hpp"

namespace probeless::cli {
namespace {

struct DevicesOptions {
  std::string config_path;
  std::string board;
  std::string cl_platform;
  std::string cl_device;
};

std::string bytes(std::uint64_t n) {
  if (n >= (1ULL << 30)) return fmt::format("{:.1f} GiB", static_cast<double>(n) / (1ULL << 30));
  if (n >= (1ULL << 20)) return fmt::format("{:.0f} MiB", static_cast<double>(n) / (1ULL << 20));
  return fmt::format("{} KiB", n >> 10);
}

// Where a selector field came from, in the service's order (DeviceSelector::resolve): the
// command line here, then the config file, then the environment.
std::string origin(const std::string& flag, const std::string& config, const char* env) {
  if (!flag.empty()) return "command line";
  if (!config.empty()) return "config";
  const char* v = std::getenv(env);
  return (v && *v) ? env : "default";
}

void print_opencl(std::ostream& out, const DevicesOptions& opts) {
  out << "OpenCL\n";
  ServiceConfig config = load_service_config(opts.config_path, opts.board);
  if (!opts.cl_platform.empty()) config.cl_platform = opts.cl_platform;
  if (!opts.cl_device.empty()) config.cl_device = opts.cl_device;
  const auto selector = DeviceSelector::resolve(config.cl_platform, config.cl_device);

  const auto devices = list_cl_devices();
  if (devices.empty()) {
    out << "  no platform: the ICD loader found no OpenCL driver (nothing usable in "
           "/etc/OpenCL/vendors); install pocl-opencl-icd, or the board's driver\n";
    return;
  }
  const auto chosen = select_cl_device(devices, selector);
  int last_platform = -1;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const auto& d = devices[i];
    if (d.platform_index != last_platform) {
      last_platform = d.platform_index;
      out << fmt::format("  platform {}: {} ({}), {}\n", d.platform_index, d.platform_name,
                         d.platform_vendor, d.platform_version);
    }
    out << fmt::format("  {} device {}.{}: {}\n", chosen == i ? '*' : ' ', d.platform_index,
                       d.device_index, d.device_name);
    out << fmt::format("      {}, {}, {}, driver {}{}\n", d.type, d.device_version, d.c_version,
                       d.driver_version, d.available ? "" : ", NOT AVAILABLE");
    out << fmt::format(
        "      {} compute units, {} global memory ({} per buffer), {} local, work-groups "
        "up to {}\n",
        d.compute_units, bytes(d.global_mem_bytes), bytes(d.max_alloc_bytes),
        bytes(d.local_mem_bytes), d.max_work_group_size);
  }
  out << fmt::format(
      "  selector: platform '{}' ({}), device '{}' ({})\n", selector.platform_substring,
      origin(opts.cl_platform, config.cl_platform, "PROBELESS_CL_PLATFORM"),
      selector.device_substring, origin(opts.cl_device, config.cl_device, "PROBELESS_CL_DEVICE"));
  if (chosen)
    out << fmt::format("  selected: device {}.{} ({})\n", devices[*chosen].platform_index,
                       devices[*chosen].device_index, devices[*chosen].device_name);
  else
    out << "  selected: none - no available device matches; the service would not start\n";
  const auto cache = default_program_cache_dir();
  out << fmt::format("  program cache: {}\n",
                     cache.empty() ? "none (no HOME or cache dir set)" : cache.string());
}

// The GPIO chips the exposure trigger and strobe can use (docs/gpio.md), and which lines the
// config asks for.
void print_gpio(std::ostream& out, const DevicesOptions& opts) {
  out << "GPIO\n";
  const auto chips = list_gpio_chips();
  if (chips.empty())
    out << "  no chip: no /dev/gpiochip* (a board's GPIO driver, or gpio-sim in the VM "
           "tests); the exposure trigger and strobe need one\n";
  for (const auto& c : chips) {
    if (!c.error.empty())
      out << fmt::format("  {}: cannot open: {}\n", c.path, c.error);
    else
      out << fmt::format("  {} '{}': {} lines, {} in use\n", c.name, c.label, c.lines, c.used);
  }
  const ServiceConfig config = load_service_config(opts.config_path, opts.board);
  const auto line = [](const std::string& chip, int n) {
    return chip.empty() ? std::string("none") : fmt::format("'{}' line {}", chip, n);
  };
  out << fmt::format("  trigger: {}, strobe: {}\n", line(config.trigger_chip, config.trigger_line),
                     line(config.strobe_chip, config.strobe_line));
}

// DRM/KMS cards for the tethered display (docs/display.md): connectors, what is plugged in,
// the modes offered (* = preferred), and what [display] in the config would choose.
void print_display(std::ostream& out, const DevicesOptions& opts) {
  using namespace display;
  out << "Display (DRM/KMS)\n";
  const ServiceConfig config = load_service_config(opts.config_path, opts.board);
  const auto cards = list_displays();
  if (cards.empty()) out << "  no /dev/dri/card*: no KMS display driver is loaded\n";
  std::string chosen;
  for (const auto& card : cards) {
    out << fmt::format("  {} ({})\n", card.path.string(), card.driver.empty() ? "?" : card.driver);
    if (!card.error.empty()) out << "    " << card.error << '\n';
    if (card.error.empty() && card.connectors.empty()) out << "    no connectors (render only)\n";
    std::vector<ConnectorInfo> infos;
    for (const auto& c : card.connectors) {
      infos.push_back(c.info);
      std::string size = c.width_mm > 0 ? fmt::format(", {}x{} mm", c.width_mm, c.height_mm) : "";
      out << fmt::format("    {}: {}{}\n", c.info.name,
                         c.info.connected ? "connected" : "disconnected", size);
      // Wrapped at ~90 columns: an HDMI sink offers 30 modes and more.
      std::string line;
      const char* label = "      modes: ";
      for (const auto& m : c.modes) {
        // Appended piecewise: GCC 12 warns (-Wrestrict, a false positive) on operator+ here.
        std::string item = m.preferred ? "*" : "";
        item.append(to_string(m));
        if (!line.empty() && line.size() + item.size() > 80) {
          out << label << line << '\n';
          label = "             ";
          line.clear();
        }
        if (!line.empty()) line.push_back(' ');
        line.append(item);
      }
      if (!line.empty()) out << label << line << '\n';
    }
    const bool this_card = config.display.screen.card.empty() ||
                           card_path(config.display.screen.card, "/dev/dri") == card.path;
    if (!chosen.empty() || !this_card || !card.error.empty()) continue;
    try {  // the service's rules (kms_modeset.cpp), on what was just listed
      const auto ci =
          choose_connector(infos, config.display.screen.connector, card.path.filename().string());
      std::optional<ModeRequest> request;
      if (!config.display.screen.mode.empty())
        request = parse_mode_request(config.display.screen.mode);
      const auto& conn = card.connectors[ci];
      const auto mi = choose_mode(conn.modes, request, conn.info.name);
      chosen = fmt::format("{} {} {}", card.path.filename().string(), conn.info.name,
                           to_string(conn.modes[mi]));
    } catch (const DisplayError& e) {
      if (!config.display.screen.card.empty()) chosen = fmt::format("none - {}", e.what());
    }
  }
  out << fmt::format("  [display] {}: card '{}', connector '{}', mode '{}'\n",
                     config.display.enabled ? "enabled" : "disabled", config.display.screen.card,
                     config.display.screen.connector, config.display.screen.mode);
  out << "  selected: "
      << (chosen.empty() ? "none - no card has a matching connected connector" : chosen) << '\n';
}

// The sensor vendors of the configured openni2: source, or the defaults.
void print_rgbd(std::ostream& out, const DevicesOptions& opts) {
  const ServiceConfig config = load_service_config(opts.config_path, opts.board);
  const std::string_view spec = config.source;
  const bool openni = spec.starts_with("openni2:");
  const auto end = spec.find('+');
  const auto options = openni2::parse_openni2_options(
      openni ? spec.substr(8, end == std::string_view::npos ? end : end - 8) : "");
  print_rgbd_sensors(out, options.usb_vendors);
}

// What the resolved config (and board) needs that this machine does not have yet.
void print_config_needs(std::ostream& out, const DevicesOptions& opts) {
  print_needs(out, load_service_config(opts.config_path, opts.board));
}

void print_libcamera(std::ostream& out, const DevicesOptions&) {
  print_libcamera_cameras(out);
}

}  // namespace

void add_devices_command(CLI::App& app) {
  auto opts = std::make_shared<DevicesOptions>();
  auto* cmd = app.add_subcommand("devices", "List the devices probeless can use");
  cmd->add_option("--config", opts->config_path, "Service config (TOML) whose selectors apply")
      ->check(CLI::ExistingFile);
  cmd->add_option("--board", opts->board, "Board file whose selectors apply (docs/boards.md)");
  cmd->add_option("--cl-platform", opts->cl_platform, "OpenCL platform substring to select");
  cmd->add_option("--cl-device", opts->cl_device, "OpenCL device substring to select");
  cmd->callback([opts] {
    // One function per section; cameras and display connectors join this list.
    const std::vector<std::function<void(std::ostream&, const DevicesOptions&)>> sections{
        print_opencl, print_rgbd, print_libcamera, print_gpio, print_display, print_config_needs};
    for (std::size_t i = 0; i < sections.size(); ++i) {
      if (i > 0) std::cout << '\n';
      sections[i](std::cout, *opts);
    }
  });
}

}  // namespace probeless::cli

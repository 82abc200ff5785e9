// probeless devices: what this machine offers the service, one section per kind of device.
// Today OpenCL (platforms, devices, and the one the selector picks); cameras and display
// connectors are further sections of the same list.
#include <fmt/format.h>

#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli/commands.hpp"
#include "app/pipeline/service_config.hpp"
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
        print_opencl};
    for (std::size_t i = 0; i < sections.size(); ++i) {
      if (i > 0) std::cout << '\n';
      sections[i](std::cout, *opts);
    }
  });
}

}  // namespace probeless::cli

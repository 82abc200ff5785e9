#include "kernels/runtime/compute_context.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>

#include "base/hash.hpp"
#include "kernels/runtime/program_binary_cache.hpp"

namespace probeless {
namespace {

std::filesystem::path env_path(const char* name) {
  const char* v = std::getenv(name);
  return (v && *v) ? std::filesystem::path(v) : std::filesystem::path();
}

// Everything a binary depends on. The driver version is there because a driver update may
// change the binary format or fix the compiler; the source goes in as a hash and a length.
std::string binary_key(const ClDeviceInfo& d, std::string_view source, const std::string& options) {
  return fmt::format(
      "probeless opencl program v1\nplatform: {} | {}\ndevice: {} | {} | {}\ndriver: {}\n"
      "options: {}\nsource: {:016x} {}\n",
      d.platform_name, d.platform_version, d.device_name, d.device_vendor, d.device_version,
      d.driver_version, options, fnv1a64(source), source.size());
}

std::string build_log(const ::cl::Program& program, const ::cl::Device& device) {
  try {
    return program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
  } catch (const ::cl::Error&) {
    return "(no build log)";
  }
}

}  // namespace

std::filesystem::path default_program_cache_dir() {
  if (auto p = env_path("PROBELESS_CACHE_DIR"); !p.empty()) return p / "opencl";
  // systemd's CacheDirectory= may list several directories, separated by ':'; ours is first.
  if (const char* v = std::getenv("CACHE_DIRECTORY"); v && *v) {
    const std::string s(v);
    return std::filesystem::path(s.substr(0, s.find(':'))) / "opencl";
  }
  if (auto p = env_path("XDG_CACHE_HOME"); !p.empty()) return p / "probeless" / "opencl";
  if (auto p = env_path("HOME"); !p.empty()) return p / ".cache" / "probeless" / "opencl";
  return {};
}

ComputeContext::ComputeContext(const ComputeOptions& options) : profiling_(options.profiling) {
  const auto devices = list_cl_devices();
  if (devices.empty())
    throw DeviceSelectionError(
        "no OpenCL platform found: the ICD loader has no driver registered in "
        "/etc/OpenCL/vendors (install pocl-opencl-icd on a desktop, or the board's driver)");
  const auto chosen = select_cl_device(devices, options.selector);
  if (!chosen)
    throw DeviceSelectionError(
        fmt::format("no OpenCL device matches {} (set cl_platform/cl_device in the config or "
                    "PROBELESS_CL_PLATFORM/PROBELESS_CL_DEVICE); available:\n{}",
                    options.selector.describe(), format_device_list(devices)));
  info_ = devices[*chosen];
  device_ = info_.device;
  try {
    context_ = ::cl::Context(device_);
    queue_ = ::cl::CommandQueue(
        context_, device_, profiling_ ? CL_QUEUE_PROFILING_ENABLE : cl_command_queue_properties{0});
  } catch (const ::cl::Error& e) {
    throw ClError(fmt::format("creating an OpenCL context on {}", info_.device_name), e);
  }
  // CPU devices (PoCL): 64 x 4, because PoCL vectorises across a work-group's rows, and 16-wide
  // groups made the Direct matte 3x slower at 640x480 (docs/performance.md). GPUs: 16 x 8 =
  // 128 work-items, within every embedded GPU's limit and a multiple of the usual SIMD widths
  // (not yet measured on a board).
  const bool cpu = info_.type == "CPU";
  const std::size_t max_wg = std::max<std::size_t>(1, info_.max_work_group_size);
  const std::size_t lx = std::min<std::size_t>(cpu ? 64 : 16, max_wg);
  const std::size_t ly = std::max<std::size_t>(1, std::min<std::size_t>(cpu ? 4 : 8, max_wg / lx));
  local_2d_ = ::cl::NDRange(lx, ly);

  if (options.disk_cache)
    cache_dir_ = options.cache_dir.empty() ? default_program_cache_dir() : options.cache_dir;
}

std::string ComputeContext::describe() const {
  return fmt::format("{} / {} ({}, {}, {} compute units, driver {})", info_.platform_name,
                     info_.device_name, info_.type, info_.device_version, info_.compute_units,
                     info_.driver_version);
}

ProgramCacheStats ComputeContext::cache_stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

::cl::Program ComputeContext::program(std::string_view name, std::string_view source,
                                      const std::string& build_options) {
  std::lock_guard lock(mutex_);
  std::string key = build_options;
  key += '\n';
  key += source;
  if (auto it = programs_.find(key); it != programs_.end()) {
    ++stats_.memory_hits;
    return it->second;
  }
  auto program = build_or_load(name, source, build_options);
  programs_.emplace(std::move(key), program);
  return program;
}

::cl::Program ComputeContext::build_or_load(std::string_view name, std::string_view source,
                                            const std::string& options) {
  const std::vector<::cl::Device> devices{device_};
  const std::string key = binary_key(info_, source, options);
  const ProgramBinaryCache disk(cache_dir_);

  if (!cache_dir_.empty()) {
    auto entry = disk.load(name, key);
    if (entry.status == ProgramBinaryCache::Lookup::Hit) {
      try {
        ::cl::Program program(context_, devices, {std::move(entry.binary)});
        program.build(devices, options.c_str());
        ++stats_.disk_hits;
        return program;
      } catch (const ::cl::Error& e) {
        spdlog::warn("OpenCL program cache: {} rejected by the driver ({}); rebuilding",
                     disk.path_for(name, key).string(), cl_error_name(e.err()));
        entry.status = ProgramBinaryCache::Lookup::Corrupt;
      }
    }
    if (entry.status == ProgramBinaryCache::Lookup::Corrupt) {
      spdlog::warn("OpenCL program cache: discarding corrupt {}",
                   disk.path_for(name, key).string());
      disk.remove(name, key);
      ++stats_.discarded_files;
    }
  }

  ::cl::Program program(context_, std::string(source));
  try {
    program.build(devices, options.c_str());
  } catch (const ::cl::Error& e) {
    throw ClBuildError(std::string(name), options, build_log(program, device_), e.err());
  }
  ++stats_.source_builds;

  if (!cache_dir_.empty()) {
    const auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
    if (binaries.empty() || binaries.front().empty() || !disk.store(name, key, binaries.front())) {
      if (stats_.write_failures++ == 0)
        spdlog::warn(
            "OpenCL program cache: cannot write to {}; programs will be rebuilt on "
            "every start",
            cache_dir_.string());
    }
  }
  return program;
}

::cl::Kernel ComputeContext::kernel(std::string_view program_name, std::string_view source,
                                    const std::string& build_options, const char* kernel_name) {
  const auto prog = program(program_name, source, build_options);
  try {
    return ::cl::Kernel(prog, kernel_name);
  } catch (const ::cl::Error& e) {
    throw ClError(fmt::format("kernel '{}' of program '{}'", kernel_name, program_name), e);
  }
}

void ComputeContext::run_2d(const ::cl::Kernel& kernel, int width, int height) {
  if (width <= 0 || height <= 0) return;
  const ::cl::NDRange global(round_up(static_cast<std::size_t>(width), local_2d_[0]),
                             round_up(static_cast<std::size_t>(height), local_2d_[1]));
  queue_.enqueueNDRangeKernel(kernel, ::cl::NullRange, global, local_2d_);
}

void ComputeContext::run_2d(const ::cl::Kernel& kernel, const PixelRect& rect) {
  if (rect.empty()) return;
  const ::cl::NDRange offset(static_cast<std::size_t>(rect.x0), static_cast<std::size_t>(rect.y0));
  const ::cl::NDRange global(round_up(static_cast<std::size_t>(rect.width()), local_2d_[0]),
                             round_up(static_cast<std::size_t>(rect.height()), local_2d_[1]));
  queue_.enqueueNDRangeKernel(kernel, offset, global, local_2d_);
}

}  // namespace probeless

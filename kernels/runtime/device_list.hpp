#pragma once
// What OpenCL offers on this machine, and which of it a DeviceSelector picks. Shared by the
// ComputeContext (to choose) and `probeless devices` (to show the choice).
#include <CL/opencl.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace probeless {

// Case-insensitive substrings; empty matches anything. Platforms match on name or vendor
// ("pocl", "Portable", "ARM", "rusticl"), devices on name ("skylake", "Mali-G610").
struct DeviceSelector {
  std::string platform_substring;
  std::string device_substring;

  // Config values win; an empty one falls back to PROBELESS_CL_PLATFORM / PROBELESS_CL_DEVICE.
  static DeviceSelector resolve(const std::string& config_platform = {},
                                const std::string& config_device = {});
  bool empty() const { return platform_substring.empty() && device_substring.empty(); }
  std::string describe() const;  // "platform ~ 'pocl', any device" for messages
};

struct ClDeviceInfo {
  ::cl::Platform platform;
  ::cl::Device device;
  int platform_index = 0;
  int device_index = 0;  // within its platform
  std::string platform_name, platform_vendor, platform_version;
  std::string device_name, device_vendor, device_version, driver_version, c_version;
  std::string type;  // "GPU", "CPU", "accelerator", ...
  std::uint32_t compute_units = 0;
  std::uint64_t global_mem_bytes = 0;
  std::uint64_t max_alloc_bytes = 0;
  std::uint64_t local_mem_bytes = 0;
  std::size_t max_work_group_size = 0;
  bool available = true;

  bool is_pocl() const;
};

// Every device of every platform. An ICD loader with no driver installed (clGetPlatformIDs
// returns CL_PLATFORM_NOT_FOUND_KHR) is an empty list, not an error.
std::vector<ClDeviceInfo> list_cl_devices();

// The index in `devices` the selector picks, or nullopt when nothing matches. Among several
// matches: on x86-64 desktops PoCL first (the reference everyone develops and tests on), on
// boards the GPU first; then listing order. Unavailable devices are never picked.
std::optional<std::size_t> select_cl_device(const std::vector<ClDeviceInfo>& devices,
                                            const DeviceSelector& selector);

// "  [0.0] Portable Computing Language / pthread-... (CPU, OpenCL 3.0 PoCL ...)" one per line.
std::string format_device_list(const std::vector<ClDeviceInfo>& devices);

}  // namespace probeless

#include "kernels/runtime/device_list.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <mutex>

#include "kernels/runtime/cl_error.hpp"

namespace probeless {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool contains_ci(const std::string& haystack, const std::string& needle) {
  return needle.empty() || lower(haystack).find(lower(needle)) != std::string::npos;
}

std::string env_or_empty(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// Drivers pad some strings with trailing NULs or spaces.
std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "GPU";
  if (t & CL_DEVICE_TYPE_CPU) return "CPU";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

int preference(const ClDeviceInfo& d) {
#if defined(__x86_64__) || defined(_M_X64)
  return d.is_pocl() ? 0 : (d.type == "GPU" ? 1 : 2);
#else
  return d.type == "GPU" ? 0 : (d.is_pocl() ? 1 : 2);
#endif
}

}  // namespace

DeviceSelector DeviceSelector::resolve(const std::string& config_platform,
                                       const std::string& config_device) {
  DeviceSelector s;
  s.platform_substring =
      config_platform.empty() ? env_or_empty("PROBELESS_CL_PLATFORM") : config_platform;
  s.device_substring = config_device.empty() ? env_or_empty("PROBELESS_CL_DEVICE") : config_device;
  return s;
}

std::string DeviceSelector::describe() const {
  if (empty()) return "the default (no platform or device given)";
  return fmt::format("platform ~ '{}', device ~ '{}'", platform_substring, device_substring);
}

bool ClDeviceInfo::is_pocl() const {
  return contains_ci(platform_name, "Portable Computing Language") ||
         contains_ci(platform_vendor, "pocl") || contains_ci(platform_name, "pocl");
}

std::vector<ClDeviceInfo> list_cl_devices() {
  // ocl-icd loads its vendor list lazily on the first call and is not thread-safe while it
  // does: the service's processing and light threads each open a context at start, and the
  // loser of that race saw no platform at all (seen: "no OpenCL platform found" in one of
  // them). One enumeration at a time.
  static std::mutex enumeration;
  std::lock_guard lock(enumeration);
  // The raw call first: the bindings throw on CL_PLATFORM_NOT_FOUND_KHR, which only means
  // that the loader has no driver registered.
  cl_uint count = 0;
  const cl_int err = clGetPlatformIDs(0, nullptr, &count);
  if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (err == CL_SUCCESS && count == 0)) return {};
  if (err != CL_SUCCESS) throw ClError("clGetPlatformIDs", err);

  std::vector<::cl::Platform> platforms;
  ::cl::Platform::get(&platforms);
  std::vector<ClDeviceInfo> out;
  for (std::size_t p = 0; p < platforms.size(); ++p) {
    std::vector<::cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const ::cl::Error& e) {
      if (e.err() != CL_DEVICE_NOT_FOUND) throw;  // a platform with no device is just empty
    }
    for (std::size_t d = 0; d < devices.size(); ++d) {
      ClDeviceInfo i;
      i.platform = platforms[p];
      i.device = devices[d];
      i.platform_index = static_cast<int>(p);
      i.device_index = static_cast<int>(d);
      i.platform_name = trimmed(platforms[p].getInfo<CL_PLATFORM_NAME>());
      i.platform_vendor = trimmed(platforms[p].getInfo<CL_PLATFORM_VENDOR>());
      i.platform_version = trimmed(platforms[p].getInfo<CL_PLATFORM_VERSION>());
      const auto& dev = devices[d];
      i.device_name = trimmed(dev.getInfo<CL_DEVICE_NAME>());
      i.device_vendor = trimmed(dev.getInfo<CL_DEVICE_VENDOR>());
      i.device_version = trimmed(dev.getInfo<CL_DEVICE_VERSION>());
      i.driver_version = trimmed(dev.getInfo<CL_DRIVER_VERSION>());
      i.c_version = trimmed(dev.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
      i.type = type_name(dev.getInfo<CL_DEVICE_TYPE>());
      i.compute_units = dev.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      i.global_mem_bytes = dev.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
      i.max_alloc_bytes = dev.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      i.local_mem_bytes = dev.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
      i.max_work_group_size = dev.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
      i.available = dev.getInfo<CL_DEVICE_AVAILABLE>() != CL_FALSE;
      out.push_back(std::move(i));
    }
  }
  return out;
}

std::optional<std::size_t> select_cl_device(const std::vector<ClDeviceInfo>& devices,
                                            const DeviceSelector& selector) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const auto& d = devices[i];
    if (!d.available) continue;
    if (!contains_ci(d.platform_name, selector.platform_substring) &&
        !contains_ci(d.platform_vendor, selector.platform_substring))
      continue;
    if (!contains_ci(d.device_name, selector.device_substring)) continue;
    if (!best || preference(d) < preference(devices[*best])) best = i;
  }
  return best;
}

std::string format_device_list(const std::vector<ClDeviceInfo>& devices) {
  std::string out;
  for (const auto& d : devices)
    out += fmt::format("  [{}.{}] {} / {} ({}, {}{})\n", d.platform_index, d.device_index,
                       d.platform_name, d.device_name, d.type, d.device_version,
                       d.available ? "" : ", unavailable");
  return out;
}

}  // namespace probeless

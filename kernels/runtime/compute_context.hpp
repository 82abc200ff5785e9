#pragma once
// The OpenCL device a pipeline runs on: context, device, one in-order queue, and the program
// cache (in memory per context, binaries on disk across runs). See docs/opencl.md.
#include <CL/opencl.hpp>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

#include "core/pixel_rect.hpp"
#include "kernels/runtime/cl_error.hpp"
#include "kernels/runtime/device_list.hpp"

namespace probeless {

struct ComputeOptions {
  DeviceSelector selector = DeviceSelector::resolve();
  bool profiling = false;  // CL_QUEUE_PROFILING_ENABLE on the queue
  // Where program binaries are kept; empty = default_program_cache_dir(). Disk caching can be
  // turned off (the in-memory cache always works).
  std::filesystem::path cache_dir;
  bool disk_cache = true;
};

// $PROBELESS_CACHE_DIR/opencl, else $CACHE_DIRECTORY/opencl (systemd's CacheDirectory=), else
// $XDG_CACHE_HOME/probeless/opencl, else $HOME/.cache/probeless/opencl; empty if none is set.
std::filesystem::path default_program_cache_dir();

// What the program cache did, for tests and logs.
struct ProgramCacheStats {
  int memory_hits = 0;      // program() answered from this context's memory
  int disk_hits = 0;        // built from a cached binary
  int source_builds = 0;    // compiled from source (first run, new key, or discarded file)
  int discarded_files = 0;  // cache files that were corrupt, mismatched or rejected by the driver
  int write_failures = 0;   // binaries that could not be stored (read-only disk, ...)
};

class ComputeContext {
 public:
  // Throws DeviceSelectionError when no device matches (listing what there is).
  explicit ComputeContext(const ComputeOptions& options = {});
  ComputeContext(const ComputeContext&) = delete;
  ComputeContext& operator=(const ComputeContext&) = delete;

  const ::cl::Context& context() const { return context_; }
  const ::cl::Device& device() const { return device_; }
  ::cl::CommandQueue& queue() { return queue_; }
  const ClDeviceInfo& info() const { return info_; }
  bool profiling() const { return profiling_; }

  // The program built from `source` with `build_options` ("-DRADIUS=6"), once per context;
  // across runs the binary comes from the disk cache when the key (source text, platform,
  // device, driver version, options) matches. `name` is for logs, errors and file names.
  // Throws ClBuildError with the full log when the source does not compile.
  ::cl::Program program(std::string_view name, std::string_view source,
                        const std::string& build_options = {});
  // A fresh kernel object (kernels carry their arguments, so each stage owns its own).
  ::cl::Kernel kernel(std::string_view program_name, std::string_view source,
                      const std::string& build_options, const char* kernel_name);

  // Enqueues a 2D kernel over width x height, the global size rounded up to the local size;
  // the kernel must bound-check its ids. Empty sizes enqueue nothing.
  void run_2d(const ::cl::Kernel& kernel, int width, int height);
  // The same over the pixels of `rect` only, as a global offset: get_global_id() are the
  // pixels' own coordinates (the rounding may add ids past the rect, inside the image or not,
  // so the kernel must be right, and bound-checked, anywhere).
  void run_2d(const ::cl::Kernel& kernel, const PixelRect& rect);
  // The local size run_2d uses (chosen per device type, docs/opencl.md).
  ::cl::NDRange local_2d() const { return local_2d_; }

  // "Portable Computing Language 3.1 / pthread-skylake-avx512 (CPU, OpenCL 3.0, 2 compute
  // units, driver 3.1)" for logs.
  std::string describe() const;

  ProgramCacheStats cache_stats() const;
  const std::filesystem::path& cache_dir() const { return cache_dir_; }  // empty: no disk cache

 private:
  ::cl::Program build_or_load(std::string_view name, std::string_view source,
                              const std::string& options);

  ClDeviceInfo info_;
  ::cl::Context context_;
  ::cl::Device device_;
  ::cl::CommandQueue queue_;
  ::cl::NDRange local_2d_;
  bool profiling_ = false;
  std::filesystem::path cache_dir_;

  mutable std::mutex mutex_;  // guards the program map and the stats
  std::map<std::string, ::cl::Program> programs_;
  ProgramCacheStats stats_;
};

// Smallest multiple of `local` that is >= n.
inline std::size_t round_up(std::size_t n, std::size_t local) {
  return local == 0 ? n : (n + local - 1) / local * local;
}

}  // namespace probeless

#pragma once
// The HDR surfel map of issue #21 item 1 on the OpenCL device (surfel_map.cl; thesis 6.2.2,
// 6.2.6; docs/fusion.md "The surfel map on the device"): the surfels live in device buffers
// and every step of a frame is a kernel, with the CPU reference's rules and parameters
// (surfel_map_reference.hpp, SurfelMapParams shared) and the reference's order of surfels
// (kept ones in order, then births in row-major order), so the two maps agree surfel for
// surfel up to float rounding; the tests compare them with stated tolerances.
#include <CL/opencl.hpp>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pixel_rect.hpp"
#include "core/pose.hpp"
#include "kernels/fusion/surfel_map_params.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::fusion {

// The device map's surfels as other kernels read them in place (the per-object environment,
// surfel_environment.hpp): one float buffer of planes, surfel i's value of plane p at
// p * capacity + i (surfel_map.cl's P_X ... RAD_B), surfels 0 .. count - 1 in the map's order.
struct SurfelPlanes {
  enum Plane : int {
    kX = 0,
    kY,
    kZ,
    kNormalX,
    kNormalY,
    kNormalZ,
    kRadius,
    kConfidence,
    kRadianceR,
    kRadianceG,
    kRadianceB,
    kPlanes
  };
  ::cl::Buffer floats;
  std::size_t capacity = 0;
  std::size_t count = 0;
};

class SurfelMapDevice {
 public:
  // Builds the programs (the first frame does not compile). Throws std::invalid_argument for
  // params out of range (check_surfel_map_params), std::runtime_error on a device without
  // 64-bit atomics (the index map's nearest-wins is an atom_min on depth | index).
  explicit SurfelMapDevice(ComputeContext& ctx, SurfelMapParams params = {});
  SurfelMapDevice(const SurfelMapDevice&) = delete;
  SurfelMapDevice& operator=(const SurfelMapDevice&) = delete;

  // One registered RGB-D frame, as SurfelMap::integrate (the same inputs, checks and
  // messages, "SurfelMapDevice::integrate: depth is 32x48, intrinsics say 64x48"). The host
  // images are read in place (CL_MEM_USE_HOST_PTR); the call returns when the frame's
  // counts are known, so they may be freed afterwards. Waits for the device.
  SurfelIntegrationStats integrate(const DepthImage& depth, const ImageRGB8& colour,
                                   const std::array<float, 3>& radiance_per_unit,
                                   const PinholeIntrinsics& intrinsics, const Pose& T_world_camera,
                                   std::int64_t frame_index);
  // The same from images already on the device (the service's upload).
  SurfelIntegrationStats integrate(const DeviceDepthImage& depth, const DeviceImageRGB8& colour,
                                   const std::array<float, 3>& radiance_per_unit,
                                   const PinholeIntrinsics& intrinsics, const Pose& T_world_camera,
                                   std::int64_t frame_index);

  // The virtual content moved: the budget's sphere follows it from the next frame on.
  void set_region_centre(const Eigen::Vector3f& centre) { params_.region_centre = centre; }

  // The map as the reference's surfels, in the device's order (blocking read).
  std::vector<Surfel> download();
  std::size_t size() const { return count_; }
  // The map's own buffer, read-only to the caller: enqueue its readers on this context's
  // (in-order) queue before the next integrate() in host order, which may swap or regrow the
  // copy these planes name; the commands already enqueued still see this frame's map.
  SurfelPlanes planes() const { return {sets_[current_].floats, sets_[current_].capacity, count_}; }
  const SurfelMapParams& params() const { return params_; }

 private:
  // One copy of the map: the structure of arrays of surfel_map.cl (kFloatPlanes float planes,
  // two long planes, a byte of flags), each plane `capacity` long.
  struct SurfelSet {
    ::cl::Buffer floats, frames, flags;
    std::size_t capacity = 0;
  };
  void prepare_frame_buffers(const PinholeIntrinsics& k);
  void ensure_capacity(std::size_t needed);
  void evict(std::size_t excess);
  void run_1d(const ::cl::Kernel& kernel, std::size_t items, std::size_t local);
  // The padded depth's border: the smoothing's radius, at least the violation test's 1 px.
  int pad() const { return std::max(params_.normal_smoothing_px, 1); }

  ComputeContext& ctx_;
  SurfelMapParams params_;
  ::cl::Kernel clear_, project_, mask_, smooth_, fuse_, count_rows_, keep_rule_, scan_, compact_,
      births_, histogram_, select_, keep_below_;
  SurfelSet sets_[2];
  int current_ = 0;
  std::size_t count_ = 0;      // surfels in sets_[current_]
  std::size_t projected_ = 0;  // entries of cells_ written by the last projection
  // Per surfel (capacity): the projection's cell (to clear the index map), the violation
  // flag, the keep flag; per block of kBlock surfels: kept, violated, stale counts.
  ::cl::Buffer cells_, violated_, keep_, block_kept_, block_violated_, block_stale_;
  // Per pixel: the index map (index_scale^2 cells a pixel, depth bits << 32 | index), the
  // depth in metres padded by the smoothing radius, the smoothed depth, the nearest depth in its 3
  // x 3 pixels, the candidate mask, what the pixel did, the radial weight (from the host's
  // std::hypot and std::exp, as the reference computes it).
  ::cl::Buffer index_map_, padded_depth_, smoothed_, nearest3_, mask_buf_, codes_, radial_weight_;
  int width_ = 0, height_ = 0;
  float weight_cx_ = 0, weight_cy_ = 0;
  // Per row of the frame: fused and born counts (the births' offsets after the scan).
  ::cl::Buffer fused_rows_, born_rows_;
  ::cl::Buffer linear_, totals_, histogram_buf_, select_state_;
  std::array<cl_uint, 8> select_init_{};  // the eviction's initial select state (host copy)
};

}  // namespace probeless::fusion

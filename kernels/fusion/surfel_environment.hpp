#pragma once
// The per-object environment of issue #21 item 5 on the OpenCL device (surfel_environment.cl;
// thesis 6.2.7; docs/fusion.md "The per-object environment on the device"): the surfels of the
// device map, read in place, splatted over the keyframe's texels as seen from the object's
// centre, then the dilate/erode gap fill, with the CPU reference's rules, options and
// arithmetic (surfel_environment_reference.hpp), so that the two agree texel for texel except
// where the device's atan and cos round a splat's edge the other way (the tests' tolerance).
#include <CL/opencl.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/fusion/surfel_environment_reference.hpp"
#include "kernels/fusion/surfel_map.hpp"
#include "kernels/runtime/compute_context.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::fusion {

using DeviceTexels = DeviceImage<float, 4>;  // envmap::ImageRGBAF's layout, n x 6n

// Host surfels as the device map's planes (capacity = count; blocking upload): the reference's
// surfel vectors for the tests and the host overload below. Throws std::invalid_argument for
// more than 2^31 - 1 surfels.
SurfelPlanes upload_surfel_planes(ComputeContext& ctx, const std::vector<Surfel>& surfels);

class SurfelEnvironmentDevice {
 public:
  // The largest face it takes: its per-texel buffers are 25 bytes a texel (key 8, source 4,
  // code 1, direction 12; 39 MB at 512, 5.5 MB at 192), and 512 is twice the largest keyframe
  // measured (docs/light-capture.md: the service's 192, 256 tried).
  static constexpr int kMaxFaceSize = 512;

  // Builds the program. Throws std::runtime_error on a device without 64-bit atomics (the
  // nearest-wins per texel is an atom_min on distance | index).
  explicit SurfelEnvironmentDevice(ComputeContext& ctx);
  SurfelEnvironmentDevice(const SurfelEnvironmentDevice&) = delete;
  SurfelEnvironmentDevice& operator=(const SurfelEnvironmentDevice&) = delete;

  // The environment seen from `centre` (world), in place as the reference's: `texels` (n x
  // 6n, the keyframe seen from there) with `surfels` (the device map's planes,
  // SurfelMapDevice::planes(), read in place) splatted over it; only the covered and filled
  // texels are written (a caller that keeps its keyframe copies it first: a 3.5 MB copy at 192
  // px, which the resolve pass used to do and which was half its cost). Enqueues on the
  // context's queue and does not wait. Throws std::invalid_argument for texels not n x 6n (1 <=
  // n <= kMaxFaceSize), options out of range (the reference's checks), planes shorter than their
  // count or more than 2^31 - 1 surfels, before it enqueues anything.
  void render(const SurfelPlanes& surfels, const Eigen::Vector3f& centre, DeviceTexels& texels,
              const SurfelEnvironmentOptions& options = {});
  // The reference's signature: host surfels (uploaded) and host texels, changed in place as
  // render_surfels_into_environment() changes them. Waits for the device.
  SurfelEnvironmentStats render(const std::vector<Surfel>& surfels, const Eigen::Vector3f& centre,
                                envmap::ImageRGBAF& texels,
                                const SurfelEnvironmentOptions& options = {});
  // The same from the device map's planes into host texels (the judge). Waits.
  SurfelEnvironmentStats render(const SurfelPlanes& surfels, const Eigen::Vector3f& centre,
                                envmap::ImageRGBAF& texels,
                                const SurfelEnvironmentOptions& options = {});

  // The last render()'s counts, as the reference's (blocking: reads per-surfel and per-texel
  // codes back; for tests and the judge, not per frame).
  SurfelEnvironmentStats last_stats();

 private:
  void ensure_texel_buffers(int n);

  ComputeContext& ctx_;
  ::cl::Kernel prepare_, splat_, dilate_, resolve_;
  // Per texel: its direction (3 planes, the host's, as the reference computes it), the nearest
  // splat (distance bits << 32 | surfel index), the surfel the texel shows after the dilate (its
  // top bit: dilated, not covered), what the resolve wrote.
  ::cl::Buffer directions_, keys_, source_, codes_;
  int face_size_ = 0;
  // Per surfel of the last render: the prepared splat (direction, cos of the angular radius,
  // distance, centre texel), its window's reach, drawn or not (the stats' surfels_drawn).
  ::cl::Buffer splats_, reaches_, drawn_;
  std::size_t drawn_capacity_ = 0, last_count_ = 0;
  DeviceTexels host_texels_;  // the host overloads' copy of their texels
};

}  // namespace probeless::fusion

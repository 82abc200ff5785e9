#pragma once
// Updates an environment-map keyframe from one fisheye frame: every texel the fisheye sees,
// by the Kalman or the best-score rule (envmap_update.cl; docs/light-capture.md).
#include <cstdint>

#include "core/exposure.hpp"
#include "kernels/envmap/envmap_types.hpp"
#include "kernels/hdr/hdr_conversion.hpp"
#include "kernels/runtime/device_image.hpp"

namespace probeless::envmap {

class EnvmapUpdate {
 public:
  // hdr: the conversion update_raw applies to the raw samples it reads (validated here).
  EnvmapUpdate(ComputeContext& ctx, const UpdateParams& params = {},
               const HdrConversionParams& hdr = {});
  const UpdateParams& params() const { return params_; }
  const HdrConversionParams& hdr_params() const { return hdr_; }

  // image: a converted frame (rgb radiance, a quality, 0 = unusable), of the size of the
  // camera view.lut was built from (std::invalid_argument naming both otherwise). texels and
  // pending: n x 6n; pending holds the best-score rule's samples of the current cycle and must
  // start zeroed (the Kalman rule ignores it). publish: this frame ends a bracket cycle (best-score
  // writes the cycle's best samples into texels and clears pending). view.room: parallax
  // with a room box (envmap_types.hpp). Enqueues only.
  void update(const DeviceImage<float, 4>& image, const FisheyeView& view, bool publish,
              DeviceImage<float, 4>& texels, DeviceImage<float, 4>& pending);
  // The same from the raw frame, converting only the pixels the texels read, exactly as
  // HdrConversion::convert(raw, bit_depth, black_level, exposure) with hdr_params() would
  // (same arguments, same std::invalid_argument on bad ones), without writing the converted
  // frame: the result equals update() on that conversion.
  void update_raw(const DeviceImage<std::uint16_t, 3>& raw, int bit_depth,
                  std::uint16_t black_level, const Exposure& exposure, const FisheyeView& view,
                  bool publish, DeviceImage<float, 4>& texels, DeviceImage<float, 4>& pending);

 private:
  // Sets the arguments from `first` on: texel geometry, camera, parallax and rule.
  void set_view_args(::cl::Kernel& kernel, int first, int n, const FisheyeView& view, bool publish);
  static float cull_cos(const FisheyeView& view, const ParallaxConstants& p);
  static void check(const DeviceImage<float, 4>& texels, const DeviceImage<float, 4>& pending);
  static void check_frame(const FisheyeView& view, int width, int height);
  const ::cl::Buffer& device_lut(const FisheyeView& view);

  ComputeContext& ctx_;
  UpdateParams params_;
  HdrConversionParams hdr_;
  ::cl::Kernel converted_, raw_;
  std::shared_ptr<const FisheyeLut> lut_;  // the table lut_device_ holds
  DeviceImage<float, 2> lut_device_;
};

}  // namespace probeless::envmap

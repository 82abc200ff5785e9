#pragma once
// Plain C++ of envmap_update.cl, step for step in float, for the kernel tests.
#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/hdr/hdr_conversion_reference.hpp"

namespace probeless::envmap {

// The converted image's sample (rgb, quality) seen along a world direction (from the
// fisheye's centre: parallax_direction has been applied), or nullopt when
// the fisheye does not see it or a neighbour pixel is unusable.
std::optional<Eigen::Vector4f> sample_fisheye_reference(const ImageRGBAF& image,
                                                        const FisheyeView& view,
                                                        const Eigen::Vector3f& world_direction);

// The fisheye pixel the kernel samples for a direction in the camera frame: the table
// (fisheye_lut.hpp) at the direction's ideal equidistant projection, bilinearly; nullopt where
// the kernel would not sample (outside the table, a cell the model cannot see, straight back).
std::optional<Eigen::Vector2f> lut_pixel_reference(const FisheyeLut& lut, const Eigen::Vector3f& p);

// The texel's world direction exactly as the kernel computes it (not normalised).
Eigen::Vector3f texel_direction_reference(int face, int x, int y, int n);

void envmap_update_reference(const ImageRGBAF& image, const FisheyeView& view,
                             const UpdateParams& params, bool publish, ImageRGBAF& texels,
                             ImageRGBAF& pending);

// EnvmapUpdate::update_raw's reference: the HDR conversion's reference, then the update's.
void envmap_update_raw_reference(const ImageRGB16& raw, int bit_depth, std::uint16_t black_level,
                                 const Exposure& exposure, const HdrConversionParams& hdr,
                                 const FisheyeView& view, const UpdateParams& params, bool publish,
                                 ImageRGBAF& texels, ImageRGBAF& pending);

}  // namespace probeless::envmap

#pragma once
// A keyframe seen from another position through the room box (docs/light-capture.md
// "Parallax"): what an object away from the keyframe's position sees. CPU only: `eval light`
// reprojects a host copy at its 32 px compare resolution once per run (~10 ms), and the
// service needs only the object's SH, for which the reprojection is folded into the SH table
// once per keyframe (light::ShProjector); an OpenCL version run per frame for the SH cost 1 ms
// (2 x 2 samples per 32 px texel) to 3 ms (4 x 4) on PoCL, the table nothing.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap {

// Texel directions d from `target` -> directions from the keyframe's position to the same
// wall point (parallax_direction with offset target - keyframe, the box relative to target).
// Disabled (directions kept) without a room or when either position is outside it.
ParallaxConstants reprojection_constants(const std::optional<RoomBox>& room,
                                         const Eigen::Vector3d& keyframe_position,
                                         const Eigen::Vector3d& target);

// How a keyframe is sampled between its texel centres.
enum class Resampling {
  // The four nearest texels. A point nearer the object than the keyframe (the sim's window:
  // 1.9 m from the object, 3.6 m from the keyframe) is magnified, and nearest lookups shifted
  // its structure by up to half a keyframe texel (eval light at the object: 0.079 nearest,
  // 0.071 bilinear).
  Bilinear,
  // Catmull-Rom on the 4 x 4 nearest, clamped to the four nearest's range (no ringing around
  // a lamp). Bilinear's tent blurs the edges of the lamps, which hold most of a chrome
  // sphere's error: `eval render`'s sphere 0.131 -> 0.122 at 128 px faces, 0.103 -> 0.095 at
  // 192 (seed 1, 2026-11-26).
  CatmullRom,
};

// texels: a keyframe (n x 6n). Returns m x 6m texels, each the mean of samples x samples
// sub-texel directions from `target`, each box-projected and sampled in the keyframe (within
// its face, clamped at the edges). alpha 1 when every keyframe texel of the bilinear
// footprint with a weight was observed (alpha > 0), else 0; filled texels still give their
// rgb (the SH needs the whole sphere).
ImageRGBAF reproject_keyframe(const ImageRGBAF& texels, const Eigen::Vector3d& keyframe_position,
                              const std::optional<RoomBox>& room, const Eigen::Vector3d& target,
                              int m, int samples, Resampling resampling);

// reproject_keyframe in two halves: where each texel's samples land in the keyframe depends
// only on the two positions and the room, not on the texels, so the service builds it once
// per keyframe and applies it at every publish (at 192 px faces the geometry, built every
// publish, was most of a 41 ms reprojection).
class ReprojectionMap {
 public:
  // For a keyframe of n px faces; throws std::invalid_argument on sizes < 1.
  ReprojectionMap(int n, const Eigen::Vector3d& keyframe_position,
                  const std::optional<RoomBox>& room, const Eigen::Vector3d& target, int m,
                  int samples);
  // texels: n x 6n, else std::invalid_argument.
  ImageRGBAF apply(const ImageRGBAF& texels, Resampling resampling) const;

 private:
  struct Tap {
    int face, x0, y0;  // the bilinear footprint's top-left texel (may be -1 or n - 1)
    float ax, ay;      // the sample's offset from it
  };
  int n_, m_, samples_;
  std::vector<Tap> taps_;  // samples^2 per texel, in texel order
};

// Texels of `target` with alpha 0 (the keyframe it came from never observed them from the
// target's position) take the mean of those `others` (same size, reprojected to the same
// position) that observed them (alpha 1), and alpha 1. A keyframe at the fisheye's height sees
// a wall only down to a few degrees below its horizon, so from an object lower down a band of
// wall just above the object's horizon is unobserved in the nearest keyframe, but observed in
// keyframes farther from that wall (docs/light-capture.md "Parallax"). Returns the texels
// filled. Throws std::invalid_argument when sizes differ.
int fill_unobserved(ImageRGBAF& target, const std::vector<const ImageRGBAF*>& others);

}  // namespace probeless::envmap

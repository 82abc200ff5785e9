#pragma once
// The environment map of one virtual object (issue #21 item 5, thesis 6.2.7; docs/fusion.md
// "The per-object environment (CPU reference)"): the nearest keyframe as seen from the
// object's position is the background, every surfel of the map is splatted over it as seen
// from there, and the holes between splats are closed with one dilate and one erode pass.
// Plain sequential C++, the reference an OpenCL kernel will be tested against; used today by
// the judge (`eval render --scene`, lab/eval/moving_scene_eval.cpp), not by the service.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "kernels/envmap/envmap_types.hpp"
#include "kernels/fusion/surfel_map_reference.hpp"

namespace probeless::fusion {

struct SurfelEnvironmentOptions {
  // The keyframe's texels carry no depth, so a surfel cannot be depth-tested against them.
  // The rule: a surfel nearer than this always wins over the keyframe. The keyframe shows the
  // room (its walls through the room box, metres away), and the map only holds surfels in its
  // region around the object, so this is the map's region radius: everything the map keeps is
  // nearer than what the keyframe shows, and a surfel left outside after the region moved
  // (SurfelMap::set_region_centre) is left to the keyframe.
  float max_distance_m = 0.5f;
  // Nearer than this the centre is on the surfel (its direction is undefined): skipped.
  float min_distance_m = 0.005f;
  // A splat's angular radius is atan(radius / distance), at most this (a surfel almost at the
  // centre would otherwise cover a whole face).
  float max_splat_rad = 0.5f;
  // 6.2.7's gap fill: one dilate then one erode pass over the covered texels (a morphological
  // closing) fills holes up to two texels wide between splats and keeps the silhouettes.
  bool gap_fill = true;
};

struct SurfelEnvironmentStats {
  std::size_t surfels_drawn = 0;   // within [min_distance_m, max_distance_m]
  std::size_t texels_covered = 0;  // by a splat
  std::size_t texels_filled = 0;   // by the gap fill
};

// Splats `surfels` into `texels` (envmap::ImageRGBAF, n x 6n, envmap_types.hpp layout: the
// keyframe seen from `centre`, the background) as seen from `centre`, world frame:
// - every surfel, back faces included (6.2.7: the object sees sides of real things that the
//   RGB-D camera saw only edge-on or from behind; culling them leaves holes onto the room);
// - as a disc of angular radius atan(radius / distance) around its direction, isotropic: its
//   orientation is ignored, so a surfel seen edge-on covers as much as one seen face-on (ours:
//   fills the sides the camera saw at a grazing angle, at the cost of fattening edges by up to
//   a surfel radius); its centre texel is always covered, however small it looks;
// - a per-texel nearest-distance test between surfels; the nearest's radiance replaces the
//   keyframe's rgb and the texel's alpha becomes 1 (observed);
// - then the gap fill: a texel no splat covered, whose 8 neighbours on its face (dilate) were
//   covered, takes the nearest such neighbour's radiance if after that every one of its 8
//   neighbours is covered or filled (erode). Neighbours across a face edge count as not
//   covered, so the fill never crosses a face edge (ours: simpler than the thesis's cube-map
//   passes, at the cost of gaps one texel wide along face edges staying open).
// Throws std::invalid_argument when texels is not n x 6n or an option is out of range.
SurfelEnvironmentStats render_surfels_into_environment(
    const std::vector<Surfel>& surfels, const Eigen::Vector3f& centre, envmap::ImageRGBAF& texels,
    const SurfelEnvironmentOptions& options = {});

}  // namespace probeless::fusion

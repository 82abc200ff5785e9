#pragma once
// Latitude-longitude (equirectangular) environment maps in the world frame (z up), in the
// convention of the USC ICT high-resolution light probes that ../shared/data/hdr/probes come
// from: row 0 is the zenith (+z), the image centre looks along -y, three quarters across along
// +x, the left and right edges along +y. With u, v in [0, 1] (pixel centres at (i + 0.5) / n):
//   azimuth = pi (2u - 1), polar = pi v,
//   direction = (sin polar sin azimuth, -sin polar cos azimuth, cos polar).
// docs/lighting-math.md has the details and how the convention was checked.
#include <Eigen/Core>

#include "core/cubemap.hpp"
#include "core/image.hpp"

namespace probeless {

Eigen::Vector3d latlong_direction(double u, double v);
// Direction (need not be unit) -> (u, v); u in [0, 1), v in [0, 1].
Eigen::Vector2d latlong_uv(const Eigen::Vector3d& direction);
// Direction through the centre of pixel (x, y) of a width x height map.
Eigen::Vector3d latlong_pixel_direction(int x, int y, int width, int height);
// Exact solid angle of any pixel in row y: (cos polar0 - cos polar1) 2 pi / width.
double latlong_pixel_solid_angle(int y, int width, int height);

// Bilinear lookup, wrapping around in azimuth and clamping at the poles.
Eigen::Vector3f sample_latlong(const ImageRGBF& latlong, const Eigen::Vector3d& direction);

// Resampling between the two layouts: every output pixel averages `supersample`^2 bilinear
// lookups spread over its area, which is enough when the resolutions are comparable.
Cubemap cubemap_from_latlong(const ImageRGBF& latlong, int face_size, int supersample = 2);
ImageRGBF latlong_from_cubemap(const Cubemap& cubemap, int width, int height, int supersample = 2);

}  // namespace probeless

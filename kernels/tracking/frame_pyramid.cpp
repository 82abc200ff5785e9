#include "kernels/tracking/frame_pyramid.hpp"

#include <algorithm>

#include "kernels/tracking/dense_tracker.hpp"

namespace probeless::tracking {

LevelCamera level_camera(const PinholeIntrinsics& camera, int level) {
  LevelCamera c{camera.width,     camera.height,    float(camera.fx),
                float(camera.fy), float(camera.cx), float(camera.cy)};
  for (int i = 0; i < level; ++i) {
    c.width /= 2;
    c.height /= 2;
    c.fx *= 0.5f;
    c.fy *= 0.5f;
    c.cx = (c.cx + 0.5f) * 0.5f - 0.5f;
    c.cy = (c.cy + 0.5f) * 0.5f - 0.5f;
  }
  return c;
}

float block_depth(const float* d, int n) {
  float nearest = 0.0f;
  for (int i = 0; i < n; ++i)
    if (d[i] > 0.0f && (nearest == 0.0f || d[i] < nearest)) nearest = d[i];
  if (nearest == 0.0f) return 0.0f;
  float sum = 0.0f;
  int count = 0;
  for (int i = 0; i < n; ++i)
    if (d[i] > 0.0f && d[i] <= nearest * 1.05f) {
      sum += d[i];
      ++count;
    }
  return sum / float(count);
}

namespace {

float metres(std::uint16_t mm, const DenseTrackerParams& p) {
  const float z = float(mm) * 0.001f;
  return z >= p.min_depth_m && z <= p.max_depth_m ? z : 0.0f;
}

// The finest level straight from the frame: grey and metres, 2x2-averaged when factor is 2.
void finest_level(const ImageRGB8& colour, const DepthImage& depth_mm, int factor,
                  const DenseTrackerParams& p, FrameLevel& out) {
  const int w = out.camera.width, h = out.camera.height;
  out.intensity = ImageF(w, h);
  out.depth_m = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (factor == 1) {
        out.intensity.at(x, y) = luma(&colour.at(x, y));
        out.depth_m.at(x, y) = metres(depth_mm.at(x, y), p);
        continue;
      }
      const int x0 = 2 * x, y0 = 2 * y;
      out.intensity.at(x, y) =
          0.25f * (luma(&colour.at(x0, y0)) + luma(&colour.at(x0 + 1, y0)) +
                   luma(&colour.at(x0, y0 + 1)) + luma(&colour.at(x0 + 1, y0 + 1)));
      const float d[4] = {metres(depth_mm.at(x0, y0), p), metres(depth_mm.at(x0 + 1, y0), p),
                          metres(depth_mm.at(x0, y0 + 1), p),
                          metres(depth_mm.at(x0 + 1, y0 + 1), p)};
      out.depth_m.at(x, y) = block_depth(d, 4);
    }
}

void halve(const FrameLevel& in, FrameLevel& out) {
  const int w = out.camera.width, h = out.camera.height;
  out.intensity = ImageF(w, h);
  out.depth_m = ImageF(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = 2 * x, y0 = 2 * y;
      out.intensity.at(x, y) =
          0.25f * (in.intensity.at(x0, y0) + in.intensity.at(x0 + 1, y0) +
                   in.intensity.at(x0, y0 + 1) + in.intensity.at(x0 + 1, y0 + 1));
      const float d[4] = {in.depth_m.at(x0, y0), in.depth_m.at(x0 + 1, y0),
                          in.depth_m.at(x0, y0 + 1), in.depth_m.at(x0 + 1, y0 + 1)};
      out.depth_m.at(x, y) = block_depth(d, 4);
    }
}

}  // namespace

void build_pyramid_reference(const ImageRGB8& colour, const DepthImage& depth_mm,
                             const PinholeIntrinsics& camera, const DenseTrackerParams& params,
                             FramePyramid& pyramid) {
  pyramid.levels.resize(std::size_t(params.levels));
  for (int i = 0; i < params.levels; ++i)
    pyramid.levels[std::size_t(i)].camera = level_camera(camera, params.finest_level + i);
  finest_level(colour, depth_mm, params.finest_level == 0 ? 1 : 2, params, pyramid.levels[0]);
  for (std::size_t i = 1; i < pyramid.levels.size(); ++i)
    halve(pyramid.levels[i - 1], pyramid.levels[i]);
}

}  // namespace probeless::tracking

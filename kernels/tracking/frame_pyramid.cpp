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

std::vector<float> undistortion_map(const PinholeCamera& camera, int finest_level) {
  if (camera.distortion().is_zero()) return {};
  const auto& k = camera.intrinsics();
  const LevelCamera c = level_camera(k, finest_level);
  const double scale = double(1 << finest_level);
  std::vector<float> map;
  map.reserve(std::size_t(c.width) * std::size_t(c.height) * 2);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      // Full-resolution pixel centre, its ray, the distorted pixel, back to the level.
      const double fx = (x + 0.5) * scale - 0.5, fy = (y + 0.5) * scale - 0.5;
      const auto p = camera.project({(fx - k.cx) / k.fx, (fy - k.cy) / k.fy, 1.0});
      map.push_back(p ? float((p->x() + 0.5) / scale - 0.5) : -1.0f);
      map.push_back(p ? float((p->y() + 0.5) / scale - 0.5) : -1.0f);
    }
  return map;
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

// Intensity bilinear (clamped at the border), depth from the nearest pixel (interpolating
// depth across an edge would invent surfaces); outside the distorted image: no depth.
void undistort_level(const std::vector<float>& map, FrameLevel& level) {
  const int w = level.camera.width, h = level.camera.height;
  const ImageF intensity = level.intensity, depth = level.depth_m;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
      const float u = map[2 * i], v = map[2 * i + 1];
      if (!(u >= 0.0f && v >= 0.0f && u <= float(w - 1) && v <= float(h - 1))) {
        level.intensity.at(x, y) = intensity.at(x, y);
        level.depth_m.at(x, y) = 0.0f;
        continue;
      }
      const int x0 = std::min(int(u), w - 2), y0 = std::min(int(v), h - 2);
      const float ax = u - float(x0), ay = v - float(y0);
      level.intensity.at(x, y) =
          (1.0f - ay) * ((1.0f - ax) * intensity.at(x0, y0) + ax * intensity.at(x0 + 1, y0)) +
          ay * ((1.0f - ax) * intensity.at(x0, y0 + 1) + ax * intensity.at(x0 + 1, y0 + 1));
      level.depth_m.at(x, y) = depth.at(int(u + 0.5f), int(v + 0.5f));
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
                             const std::vector<float>& undistort, FramePyramid& pyramid) {
  pyramid.levels.resize(std::size_t(params.levels));
  for (int i = 0; i < params.levels; ++i)
    pyramid.levels[std::size_t(i)].camera = level_camera(camera, params.finest_level + i);
  finest_level(colour, depth_mm, params.finest_level == 0 ? 1 : 2, params, pyramid.levels[0]);
  if (!undistort.empty()) undistort_level(undistort, pyramid.levels[0]);
  for (std::size_t i = 1; i < pyramid.levels.size(); ++i)
    halve(pyramid.levels[i - 1], pyramid.levels[i]);
}

}  // namespace probeless::tracking

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

float metres(std::uint16_t mm, float min_m, float max_m) {
  const float z = float(mm) * 0.001f;
  return z >= min_m && z <= max_m ? z : 0.0f;
}

// Frames keep their size: the level images are reused, not reallocated, per frame.
void ensure_size(FrameLevel& level) {
  const int w = level.camera.width, h = level.camera.height;
  if (level.intensity.width() != w || level.intensity.height() != h) {
    level.intensity = ImageF(w, h);
    level.depth_m = ImageF(w, h);
  }
}

// The finest level straight from the frame: grey and metres, 2x2-averaged when factor is 2.
void finest_level(const ImageRGB8& colour, const DepthImage& depth_mm, int factor,
                  const DenseTrackerParams& p, FrameLevel& out) {
  ensure_size(out);
  const int w = out.camera.width, h = out.camera.height;
  const float lo = p.min_depth_m, hi = p.max_depth_m;
  for (int y = 0; y < h; ++y) {
    float* grey = out.intensity.row(y);
    float* depth = out.depth_m.row(y);
    if (factor == 1) {
      const std::uint8_t* c = colour.row(y);
      const std::uint16_t* d = depth_mm.row(y);
      for (int x = 0; x < w; ++x) {
        grey[x] = luma(c + 3 * x);
        depth[x] = metres(d[x], lo, hi);
      }
      continue;
    }
    const std::uint8_t *c0 = colour.row(2 * y), *c1 = colour.row(2 * y + 1);
    const std::uint16_t *d0 = depth_mm.row(2 * y), *d1 = depth_mm.row(2 * y + 1);
    for (int x = 0; x < w; ++x) {
      const int s = 2 * x;
      // The luma of the 2x2 sum of each channel (integers, exact), then the average.
      const std::uint8_t *a = c0 + 3 * s, *b = c1 + 3 * s;
      const int r = a[0] + a[3] + b[0] + b[3], g = a[1] + a[4] + b[1] + b[4],
                bl = a[2] + a[5] + b[2] + b[5];
      grey[x] = 0.25f * (0.299f * float(r) + 0.587f * float(g) + 0.114f * float(bl));
      const float d[4] = {metres(d0[s], lo, hi), metres(d0[s + 1], lo, hi), metres(d1[s], lo, hi),
                          metres(d1[s + 1], lo, hi)};
      depth[x] = block_depth(d, 4);
    }
  }
}

// Intensity bilinear, depth from the nearest pixel (interpolating depth across an edge would
// invent surfaces); where the map leaves the distorted image: its own grey, no depth.
void undistort_level(const std::vector<float>& map, const FrameLevel& in, FrameLevel& out) {
  const int w = out.camera.width, h = out.camera.height;
  const float* grey = in.intensity.data();
  const float* depth = in.depth_m.data();
  for (int y = 0; y < h; ++y) {
    float* out_grey = out.intensity.row(y);
    float* out_depth = out.depth_m.row(y);
    const float* m = map.data() + 2 * std::size_t(y) * std::size_t(w);
    for (int x = 0; x < w; ++x) {
      const float u = m[2 * x], v = m[2 * x + 1];
      if (!(u >= 0.0f && v >= 0.0f && u <= float(w - 1) && v <= float(h - 1))) {
        out_grey[x] = grey[y * w + x];
        out_depth[x] = 0.0f;
        continue;
      }
      const int x0 = std::min(int(u), w - 2), y0 = std::min(int(v), h - 2);
      const float ax = u - float(x0), ay = v - float(y0);
      const float* r0 = grey + y0 * w + x0;
      const float* r1 = r0 + w;
      out_grey[x] = (1.0f - ay) * ((1.0f - ax) * r0[0] + ax * r0[1]) +
                    ay * ((1.0f - ax) * r1[0] + ax * r1[1]);
      out_depth[x] = depth[int(v + 0.5f) * w + int(u + 0.5f)];
    }
  }
}

void halve(const FrameLevel& in, FrameLevel& out) {
  ensure_size(out);
  const int w = out.camera.width, h = out.camera.height;
  for (int y = 0; y < h; ++y) {
    const float *g0 = in.intensity.row(2 * y), *g1 = in.intensity.row(2 * y + 1);
    const float *d0 = in.depth_m.row(2 * y), *d1 = in.depth_m.row(2 * y + 1);
    float* grey = out.intensity.row(y);
    float* depth = out.depth_m.row(y);
    for (int x = 0; x < w; ++x) {
      const int s = 2 * x;
      grey[x] = 0.25f * (g0[s] + g0[s + 1] + g1[s] + g1[s + 1]);
      const float d[4] = {d0[s], d0[s + 1], d1[s], d1[s + 1]};
      depth[x] = block_depth(d, 4);
    }
  }
}

}  // namespace

void build_pyramid_reference(const ImageRGB8& colour, const DepthImage& depth_mm,
                             const PinholeIntrinsics& camera, const DenseTrackerParams& params,
                             const std::vector<float>& undistort, FramePyramid& pyramid) {
  pyramid.levels.resize(std::size_t(params.levels));
  for (int i = 0; i < params.levels; ++i)
    pyramid.levels[std::size_t(i)].camera = level_camera(camera, params.finest_level + i);
  const int factor = params.finest_level == 0 ? 1 : 2;
  if (undistort.empty()) {
    finest_level(colour, depth_mm, factor, params, pyramid.levels[0]);
  } else {
    pyramid.distorted.camera = pyramid.levels[0].camera;
    finest_level(colour, depth_mm, factor, params, pyramid.distorted);
    ensure_size(pyramid.levels[0]);
    undistort_level(undistort, pyramid.distorted, pyramid.levels[0]);
  }
  for (std::size_t i = 1; i < pyramid.levels.size(); ++i)
    halve(pyramid.levels[i - 1], pyramid.levels[i]);
}

}  // namespace probeless::tracking

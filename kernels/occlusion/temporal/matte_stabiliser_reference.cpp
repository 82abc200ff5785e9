#include "kernels/occlusion/temporal/matte_stabiliser_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/occlusion/cvf/hole_core_reference.hpp"

namespace probeless::occlusion {

ImageF stabilise_matte_reference(const ImageF& alpha, const StabiliserFrame& cur,
                                 const ImageF& prev_alpha, const StabiliserFrame& prev,
                                 const StabiliserMotion& motion, const StabiliserParams& p) {
  const int width = alpha.width(), height = alpha.height();
  for (const StabiliserFrame* f : {&cur, &prev}) {
    if (!f->colour || !f->real_depth_mm || !f->virtual_depth_mm)
      throw std::invalid_argument("matte stabiliser: a frame image is missing");
    if (f->colour->width() != width || f->colour->height() != height ||
        f->real_depth_mm->width() != width || f->real_depth_mm->height() != height ||
        f->virtual_depth_mm->width() != width || f->virtual_depth_mm->height() != height)
      throw std::invalid_argument("matte stabiliser: images differ in size");
  }
  if (prev_alpha.width() != width || prev_alpha.height() != height)
    throw std::invalid_argument("matte stabiliser: images differ in size");
  const Eigen::Matrix3f r = motion.T_prev_curr.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f t = (motion.T_prev_curr.translation * 1000.0).cast<float>();
  const auto fx = static_cast<float>(motion.intrinsics.fx);
  const auto fy = static_cast<float>(motion.intrinsics.fy);
  const auto cx = static_cast<float>(motion.intrinsics.cx);
  const auto cy = static_cast<float>(motion.intrinsics.cy);
  ImageF out = alpha;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float a = alpha.at(x, y);
      const float v = cur.virtual_depth_mm->at(x, y);
      if (!(v > 0.0f)) continue;
      const std::uint16_t d = cur.real_depth_mm->at(x, y);
      const float z = d > 0 ? static_cast<float>(d) : v;
      const float px = (static_cast<float>(x) - cx) / fx * z;
      const float py = (static_cast<float>(y) - cy) / fy * z;
      const float qx = r(0, 0) * px + r(0, 1) * py + r(0, 2) * z + t.x();
      const float qy = r(1, 0) * px + r(1, 1) * py + r(1, 2) * z + t.y();
      const float qz = r(2, 0) * px + r(2, 1) * py + r(2, 2) * z + t.z();
      // A near occluder's pixels move with it: the same pixel, which must have been it too.
      const bool marked = d == kNearHoleDepthMm;
      if (!(qz > 0.0f) && !marked) continue;
      const float u = marked ? static_cast<float>(x) : fx * qx / qz + cx;
      const float w = marked ? static_cast<float>(y) : fy * qy / qz + cy;
      if (!(u >= 0.0f && w >= 0.0f && u <= static_cast<float>(width - 1) &&
            w <= static_cast<float>(height - 1)))
        continue;
      const int ju = static_cast<int>(u + 0.5f), jw = static_cast<int>(w + 0.5f);
      if (!(prev.virtual_depth_mm->at(ju, jw) > 0.0f)) continue;
      const std::uint16_t dp = prev.real_depth_mm->at(ju, jw);
      if (d > 0 && !marked && dp > 0 &&
          std::fabs(qz - static_cast<float>(dp)) >
              p.depth_tolerance_mm + p.depth_tolerance_rel * qz)
        continue;
      if (marked && dp != kNearHoleDepthMm) continue;
      const int x0 = std::min(static_cast<int>(u), std::max(width - 2, 0));
      const int y0 = std::min(static_cast<int>(w), std::max(height - 2, 0));
      const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
      const float fu = u - static_cast<float>(x0), fw = w - static_cast<float>(y0);
      const int tx[4] = {x0, x1, x0, x1}, ty[4] = {y0, y0, y1, y1};
      const float wts[4] = {(1.0f - fu) * (1.0f - fw), fu * (1.0f - fw), (1.0f - fu) * fw, fu * fw};
      float sw = 0, sa = 0, sc[3] = {0, 0, 0};
      for (int k = 0; k < 4; ++k) {
        if (!(prev.virtual_depth_mm->at(tx[k], ty[k]) > 0.0f)) continue;
        sw += wts[k];
        sa += wts[k] * prev_alpha.at(tx[k], ty[k]);
        for (int c = 0; c < 3; ++c)
          sc[c] += wts[k] * static_cast<float>(prev.colour->at(tx[k], ty[k], c));
      }
      if (!(sw > 1e-6f)) continue;
      float dist = 0;
      for (int c = 0; c < 3; ++c) {
        const float dc = (sc[c] / sw - static_cast<float>(cur.colour->at(x, y, c))) / 255.0f;
        dist += dc * dc;
      }
      const float range = (d > 0) != (dp > 0) ? p.unconfirmed_colour_range : p.colour_range;
      const float q = dist / (range * range);
      if (!(q < 1.0f)) continue;
      const bool confirmed = d > 0 && dp > 0 && !marked;
      const float weight = marked      ? p.near_occluder_history_weight
                           : confirmed ? p.confirmed_history_weight
                                       : p.history_weight;
      const float h = weight * (1.0f - q);
      float blended = (1.0f - h) * a + h * (sa / sw);
      // A near occluder hides the object wherever it is: its history may hide more, never less.
      if (marked) blended = std::min(blended, a);
      if (blended < p.snap) blended = 0.0f;
      if (blended > 1.0f - p.snap) blended = 1.0f;
      out.at(x, y) = blended;
    }
  return out;
}

}  // namespace probeless::occlusion

#pragma once
// Ray-primitive intersection and shading for the synthetic room, written once for the
// renderer, the lighting bake and the light probes. Rays need not be unit length: t is in
// units of |d| (the pinhole renderer uses d with camera-z = 1, so t is the depth).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "drivers/sim/sim_world.hpp"

namespace probeless::sim {

// Scalar on purpose: a 4-wide version (slab tests on Array4f) measured 1.8x slower here,
// building vectors from scalars costs more than the lanes save.
struct Ray {
  Eigen::Vector3f o, d, inv_d;
  Ray(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir)
      : o(origin), d(dir), inv_d(1.0f / dir.x(), 1.0f / dir.y(), 1.0f / dir.z()) {}
};

// What a ray hit first. Patch hits carry the patch; others the primitive's index.
struct Hit {
  enum class Kind : std::uint8_t { Patch, Mirror, Occluder } kind = Kind::Patch;
  float t = std::numeric_limits<float>::infinity();
  int index = -1;  // patch, sphere or capsule index
};

inline void hit_room(const Ray& r, const SimWorld& w, Hit& hit) {
  const Eigen::Vector3f& lo = w.room_lo();
  const Eigen::Vector3f& hi = w.room_hi();
  float best = std::numeric_limits<float>::infinity();
  int face = 0;
  for (int a = 0; a < 3; ++a) {
    if (r.d[a] == 0) continue;
    const bool up = r.d[a] > 0;
    const float t = ((up ? hi[a] : lo[a]) - r.o[a]) * r.inv_d[a];
    if (t < best) {
      best = t;
      face = a * 2 + (up ? 1 : 0);
    }
  }
  hit = {Hit::Kind::Patch, best, w.room_patches()[face]};
}

inline bool hit_box(const Ray& r, const Box& b, Hit& hit) {
  float t_near = -std::numeric_limits<float>::infinity();
  float t_far = hit.t;
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    float t0 = (b.lo[a] - r.o[a]) * r.inv_d[a];
    float t1 = (b.hi[a] - r.o[a]) * r.inv_d[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) {
      t_near = t0;
      axis = a;
    }
    t_far = std::min(t_far, t1);
  }
  if (!(t_near <= t_far) || !(t_near > 0) || axis < 0) return false;
  const int patch = b.patch[axis * 2 + (r.d[axis] > 0 ? 0 : 1)];
  if (patch < 0) return false;
  hit = {Hit::Kind::Patch, t_near, patch};
  return true;
}

inline bool hit_sphere(const Ray& r, const Eigen::Vector3f& centre, float radius, float& t) {
  const Eigen::Vector3f oc = r.o - centre;
  const float a = r.d.squaredNorm();
  const float b = oc.dot(r.d);
  const float c = oc.squaredNorm() - radius * radius;
  const float h = b * b - a * c;
  if (h < 0) return false;
  t = (-b - std::sqrt(h)) / a;
  return t > 0;
}

// Capsule intersection after I. Quilez, generalised to rays that are not unit length.
inline bool hit_capsule(const Ray& r, const Capsule& cap, float& t) {
  const Eigen::Vector3f ba = cap.b - cap.a;
  const Eigen::Vector3f oa = r.o - cap.a;
  const float baba = ba.dot(ba), bard = ba.dot(r.d), baoa = ba.dot(oa);
  const float rdoa = r.d.dot(oa), oaoa = oa.dot(oa), dd = r.d.dot(r.d);
  const float a = baba * dd - bard * bard;
  const float b = baba * rdoa - baoa * bard;
  const float c = baba * oaoa - baoa * baoa - cap.radius * cap.radius * baba;
  float h = b * b - a * c;
  if (h < 0) return false;
  float tt = (-b - std::sqrt(h)) / a;
  const float y = baoa + tt * bard;
  if (y > 0 && y < baba) {
    t = tt;
    return t > 0;
  }
  return hit_sphere(r, y <= 0 ? cap.a : cap.b, cap.radius, t);
}

// A moving box's nearest entry in (0, t_max): t, its faces all seen (closed box).
inline bool hit_moving_box(const Ray& r, const MovingBox& b, float t_max, float& t) {
  float t_near = -std::numeric_limits<float>::infinity(), t_far = t_max;
  for (int a = 0; a < 3; ++a) {
    float t0 = (b.lo[a] - r.o[a]) * r.inv_d[a];
    float t1 = (b.hi[a] - r.o[a]) * r.inv_d[a];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
  }
  if (!(t_near <= t_far) || !(t_near > 0)) return false;
  t = t_near;
  return true;
}

// The outward normal of a moving box at a point p on its surface: the face p is nearest.
inline Eigen::Vector3f moving_box_normal(const MovingBox& b, const Eigen::Vector3f& p) {
  int best = 0;
  float best_d = std::numeric_limits<float>::infinity();
  for (int f = 0; f < 6; ++f) {
    const float d = std::fabs(p[f / 2] - (f % 2 ? b.hi[f / 2] : b.lo[f / 2]));
    if (d < best_d) {
      best_d = d;
      best = f;
    }
  }
  return Eigen::Vector3f::Unit(best / 2) * (best % 2 ? 1.0f : -1.0f);
}

// The first hit among the room and the candidates.
inline Hit trace(const Ray& r, const SimWorld& w, std::span<const PrimRef> candidates,
                 const Occluder* occluder) {
  Hit hit;
  hit_room(r, w, hit);
  for (const PrimRef& p : candidates) {
    switch (p.kind) {
      case PrimRef::Kind::Box:
        hit_box(r, w.boxes()[p.index], hit);
        break;
      case PrimRef::Kind::Sphere: {
        const Sphere& s = w.spheres()[p.index];
        float t;
        if (hit_sphere(r, s.centre, s.radius, t) && t < hit.t)
          hit = {Hit::Kind::Mirror, t, p.index};
        break;
      }
      case PrimRef::Kind::Capsule: {
        float t;
        if (occluder && hit_capsule(r, occluder->capsules[p.index], t) && t < hit.t)
          hit = {Hit::Kind::Occluder, t, p.index};
        break;
      }
      case PrimRef::Kind::OccluderBox: {
        float t;
        if (occluder && hit_moving_box(r, occluder->boxes[p.index], hit.t, t))
          hit = {Hit::Kind::Occluder, t,
                 static_cast<int>(occluder->capsules.size()) + static_cast<int>(p.index)};
        break;
      }
    }
  }
  return hit;
}

// Baked radiance of a patch at world point p, bilinear between texel centres (RGB, pad).
template <typename Point>
inline Eigen::Array4f patch_texel(const Patch& patch, int lamp_state, const Point& p) {
  const float fu = std::clamp(p[patch.axis_u] * patch.scale_u + patch.offset_u, 0.0f, patch.max_fu);
  const float fv = std::clamp(p[patch.axis_v] * patch.scale_v + patch.offset_v, 0.0f, patch.max_fv);
  const int i = static_cast<int>(fu), j = static_cast<int>(fv);
  const float au = fu - i, av = fv - j;
  const Eigen::Array4f* t00 =
      patch.radiance[lamp_state].data() + static_cast<std::size_t>(j) * patch.nu + i;
  const Eigen::Array4f* t01 = t00 + patch.nu;
  const Eigen::Array4f top = t00[0] + au * (t00[1] - t00[0]);
  const Eigen::Array4f bottom = t01[0] + au * (t01[1] - t01[0]);
  return top + av * (bottom - top);
}

inline Eigen::Vector3f patch_radiance(const Patch& patch, int lamp_state,
                                      const Eigen::Vector3f& p) {
  return patch_texel(patch, lamp_state, p).head<3>().matrix();
}

// Whether structured light measures depth at point p of a patch.
inline bool patch_has_depth(const Patch& patch, const Eigen::Vector3f& p) {
  if (patch.no_depth) return false;
  for (const auto& box : patch.no_depth_boxes) {
    if ((p.array() >= box[0].array() - 1e-3f).all() && (p.array() <= box[1].array() + 1e-3f).all())
      return false;
  }
  return true;
}

// Radiance leaving a moving thing at p with normal n and this albedo (Lambertian, the lights
// as points, no shadows): the arm's skin, and the moving-object scenes' boxes.
inline Eigen::Vector3f moving_radiance(const SimWorld& w, int lamp_state, const Eigen::Vector3f& p,
                                       const Eigen::Vector3f& n, const Eigen::Vector3f& albedo) {
  Eigen::Vector3f irradiance = w.ambient(lamp_state);
  for (const AreaLight& l : w.lights()) {
    if (l.switch_bit >= 0 && !((lamp_state >> l.switch_bit) & 1)) continue;
    const Eigen::Vector3f to = l.centre - p;
    const float r2 = to.squaredNorm();
    const Eigen::Vector3f dir = to / std::sqrt(r2);
    const float cos_s = n.dot(dir), cos_l = -l.normal.dot(dir);
    if (cos_s <= 0 || cos_l <= 0) continue;
    const float area = 4.0f * l.u_half.norm() * l.v_half.norm();
    irradiance += l.radiance * (area * cos_s * cos_l / r2);
  }
  return albedo.cwiseProduct(irradiance) * (1.0f / 3.14159265f);
}

// Radiance leaving the arm at p with normal n (Lambertian skin, lights as points, no shadows).
inline Eigen::Vector3f skin_radiance(const SimWorld& w, int lamp_state, const Eigen::Vector3f& p,
                                     const Eigen::Vector3f& n) {
  return moving_radiance(w, lamp_state, p, n, w.skin_albedo());
}

inline Eigen::Vector3f capsule_normal(const Capsule& cap, const Eigen::Vector3f& p) {
  const Eigen::Vector3f ba = cap.b - cap.a;
  const float h = std::clamp((p - cap.a).dot(ba) / ba.squaredNorm(), 0.0f, 1.0f);
  return (p - (cap.a + h * ba)).normalized();
}

// The first hit among everything static, and the occluder when given (no tile culling: for
// the odd secondary ray and the light probes).
inline Hit trace_all(const Ray& r, const SimWorld& w, const Occluder* occluder) {
  Hit hit = trace(r, w, w.static_prims(), nullptr);
  if (occluder) {
    for (int i = 0; i < static_cast<int>(occluder->capsules.size()); ++i) {
      float t;
      if (hit_capsule(r, occluder->capsules[i], t) && t < hit.t) hit = {Hit::Kind::Occluder, t, i};
    }
    const int n_capsules = static_cast<int>(occluder->capsules.size());
    for (int j = 0; j < static_cast<int>(occluder->boxes.size()); ++j) {
      float t;
      if (hit_moving_box(r, occluder->boxes[j], hit.t, t))
        hit = {Hit::Kind::Occluder, t, n_capsules + j};
    }
  }
  return hit;
}

// Radiance leaving a diffuse hit point (a patch or the arm) towards the ray's origin.
inline Eigen::Vector3f shade_diffuse(const Ray& r, const Hit& hit, const SimWorld& w,
                                     int lamp_state, const Occluder* occluder) {
  const Eigen::Vector3f p = r.o + hit.t * r.d;
  if (hit.kind == Hit::Kind::Patch) return patch_radiance(w.patches()[hit.index], lamp_state, p);
  if (hit.kind == Hit::Kind::Occluder && occluder) {
    const auto n_capsules = static_cast<int>(occluder->capsules.size());
    if (hit.index < n_capsules)
      return skin_radiance(w, lamp_state, p, capsule_normal(occluder->capsules[hit.index], p));
    const MovingBox& b = occluder->boxes[static_cast<std::size_t>(hit.index - n_capsules)];
    return moving_radiance(w, lamp_state, p, moving_box_normal(b, p), b.albedo);
  }
  return Eigen::Vector3f::Zero();
}

// Radiance leaving the hit point towards the ray's origin. A mirror hit follows one
// reflection (the ball is convex, so a reflected ray never meets it again).
inline Eigen::Vector3f shade(const Ray& r, const Hit& hit, const SimWorld& w, int lamp_state,
                             const Occluder* occluder) {
  if (hit.kind != Hit::Kind::Mirror) return shade_diffuse(r, hit, w, lamp_state, occluder);
  const Sphere& s = w.spheres()[hit.index];
  const Eigen::Vector3f p = r.o + hit.t * r.d;
  const Eigen::Vector3f n = (p - s.centre).normalized();
  const Eigen::Vector3f d = r.d.normalized();
  const Ray reflected(p + 1e-4f * n, d - 2.0f * d.dot(n) * n);
  const Hit h2 = trace_all(reflected, w, occluder);
  return s.reflectance.cwiseProduct(shade_diffuse(reflected, h2, w, lamp_state, occluder));
}

}  // namespace probeless::sim

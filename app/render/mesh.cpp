#include "app/render/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "app/render/model_loading.hpp"

namespace probeless::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// One ring of a surface of revolution about z: a point of the profile (radius, height) and
// the profile's outward normal there (radial, axial components).
struct Ring {
  float r, z, nr, nz;
};

// Sweeps the rings (bottom to top) around z. Triangles run counter-clockwise seen from
// outside: the surface normal is d/dphi x d/dprofile, which is the profile's outward normal
// for a profile that keeps the solid on its left going up. Bands between two rings at the
// same place (a crease) and triangles collapsed onto the axis are left out.
Mesh revolve(std::string name, const std::vector<Ring>& rings, int segments) {
  Mesh m;
  m.name = std::move(name);
  const int columns = segments + 1;  // the seam is duplicated so that uvs can wrap
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const Ring& ring = rings[k];
    for (int j = 0; j < columns; ++j) {
      const float phi = 2.f * kPi * static_cast<float>(j % segments) / static_cast<float>(segments);
      const float c = std::cos(phi), s = std::sin(phi);
      m.positions.emplace_back(ring.r * c, ring.r * s, ring.z);
      m.normals.push_back(Eigen::Vector3f(ring.nr * c, ring.nr * s, ring.nz).normalized());
      m.uvs.emplace_back(static_cast<float>(j) / static_cast<float>(segments),
                         static_cast<float>(k) / static_cast<float>(rings.size() - 1));
    }
  }
  for (std::size_t k = 0; k + 1 < rings.size(); ++k) {
    const Ring& lo = rings[k];
    const Ring& hi = rings[k + 1];
    if (lo.r == hi.r && lo.z == hi.z) continue;
    for (int j = 0; j < segments; ++j) {
      const auto ll = static_cast<std::uint32_t>(k * columns + j);
      const std::uint32_t lr = ll + 1, ul = ll + columns, ur = ul + 1;
      if (lo.r > 0.f) m.indices.insert(m.indices.end(), {ll, lr, ur});
      if (hi.r > 0.f) m.indices.insert(m.indices.end(), {ll, ur, ul});
    }
  }
  return m;
}

struct ProfilePoint {
  float r, z;
  bool crease;
};

// Rings with normals from a profile polyline: smooth points average the normals of the two
// segments that meet there, crease points are doubled with one normal each.
std::vector<Ring> rings_from_profile(const std::vector<ProfilePoint>& p) {
  auto segment_normal = [&](std::size_t i) {  // of the segment from p[i] to p[i+1]
    Eigen::Vector2f d(p[i + 1].r - p[i].r, p[i + 1].z - p[i].z);
    return Eigen::Vector2f(d.y(), -d.x()).normalized();
  };
  std::vector<Ring> rings;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool first = i == 0, last = i + 1 == p.size();
    auto add = [&](const Eigen::Vector2f& n) { rings.push_back({p[i].r, p[i].z, n.x(), n.y()}); };
    if (first) {
      add(segment_normal(i));
    } else if (last) {
      add(segment_normal(i - 1));
    } else if (p[i].crease) {
      add(segment_normal(i - 1));
      add(segment_normal(i));
    } else {
      add((segment_normal(i - 1) + segment_normal(i)).normalized());
    }
  }
  return rings;
}

// Appends the points of a circular arc of the profile after its start (which is the last
// point already there), angles in degrees.
void arc_to(std::vector<ProfilePoint>& out, float cr, float cz, float radius, float a0_deg,
            float a1_deg, int steps) {
  for (int i = 1; i <= steps; ++i) {
    const float a = (a0_deg + (a1_deg - a0_deg) * static_cast<float>(i) / steps) * kPi / 180.f;
    float r = cr + radius * std::cos(a);
    if (std::abs(r) < 1e-6f) r = 0.f;  // on the axis: a pole
    out.push_back({r, cz + radius * std::sin(a), false});
  }
}

}  // namespace

std::pair<Eigen::Vector3f, Eigen::Vector3f> Mesh::bounds() const {
  if (positions.empty()) return {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  Eigen::Vector3f lo = positions.front(), hi = positions.front();
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

void Mesh::validate() const {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("mesh '" + name + "': " + what);
  };
  if (normals.size() != positions.size()) fail("normals and positions differ in count");
  if (!uvs.empty() && uvs.size() != positions.size()) fail("uvs and positions differ in count");
  if (!colours.empty() && colours.size() != positions.size())
    fail("colours and positions differ in count");
  if (indices.size() % 3 != 0) fail("index count is not a multiple of 3");
  for (std::uint32_t i : indices)
    if (i >= positions.size())
      fail("index " + std::to_string(i) + " >= vertex count " + std::to_string(positions.size()));
  for (const auto& p : positions)
    if (!p.allFinite()) fail("a position is not finite");
  for (const auto& n : normals)
    if (!n.allFinite()) fail("a normal is not finite");
  if (!prt_transfer.empty()) {
    if (prt_transfer.size() != kPrtCoefficients * positions.size())
      fail("prt_transfer holds " + std::to_string(prt_transfer.size()) + " values, not " +
           std::to_string(kPrtCoefficients) + " per vertex (" +
           std::to_string(kPrtCoefficients * positions.size()) + ")");
    for (float t : prt_transfer)
      if (!std::isfinite(t)) fail("a transfer coefficient is not finite");
  }
}

Mesh make_sphere(float radius, int segments, int rings) {
  if (!(radius > 0.f) || segments < 3 || rings < 2)
    throw std::invalid_argument("make_sphere: radius > 0, segments >= 3, rings >= 2");
  std::vector<Ring> profile;
  for (int i = 0; i <= rings; ++i) {  // south pole to north pole
    const float theta = -kPi / 2 + kPi * static_cast<float>(i) / static_cast<float>(rings);
    const float c = i == 0 || i == rings ? 0.f : std::cos(theta);
    profile.push_back({radius * c, radius * std::sin(theta), c, std::sin(theta)});
  }
  return revolve("sphere", profile, segments);
}

Mesh make_box(const Eigen::Vector3f& size) {
  if (!(size.minCoeff() > 0.f)) throw std::invalid_argument("make_box: sizes must be > 0");
  Mesh m;
  m.name = "box";
  const Eigen::Vector3f h = size / 2;
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {1.f, -1.f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = sign;
      // u x v = n, so the corners below run counter-clockwise seen from outside.
      Eigen::Vector3f u = Eigen::Vector3f::Zero();
      u[(axis + 1) % 3] = 1.f;
      const Eigen::Vector3f v = n.cross(u);
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      const float su[] = {-1, 1, 1, -1}, sv[] = {-1, -1, 1, 1};
      for (int c = 0; c < 4; ++c) {
        m.positions.push_back((n + su[c] * u + sv[c] * v).cwiseProduct(h));
        m.normals.push_back(n);
        m.uvs.emplace_back((su[c] + 1) / 2, (sv[c] + 1) / 2);
      }
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

Mesh make_pawn(float height, int segments) {
  if (!(height > 0.f) || segments < 3)
    throw std::invalid_argument("make_pawn: height > 0, segments >= 3");
  // Profile in units where the top of the head is at 0.93 (a Staunton pawn, by eye): base
  // disc with a rounded rim, a cove into a tapering stem, a collar, a neck and a ball head.
  // Arcs meet their neighbours tangentially except at the creases.
  std::vector<ProfilePoint> p{{0.f, 0.f, true}, {0.33f, 0.f, true}, {0.33f, 0.035f, false}};
  arc_to(p, 0.28f, 0.035f, 0.05f, 0.f, 90.f, 6);  // rounded top of the base
  p.push_back({0.25f, 0.085f, false});
  arc_to(p, 0.25f, 0.195f, 0.11f, -90.f, -180.f, 8);  // cove up into the stem
  for (int i = 1; i <= 8; ++i) {                      // stem, gently concave
    const float t = static_cast<float>(i) / 8.f;
    p.push_back({0.10f + 0.04f * (1.f - t) * (1.f - t), 0.195f + (0.52f - 0.195f) * t, false});
  }
  p.back().crease = true;
  p.push_back({0.17f, 0.52f, false});
  arc_to(p, 0.17f, 0.56f, 0.04f, -90.f, 90.f, 8);  // collar rim
  p.push_back({0.10f, 0.60f, true});
  const float head_r = 0.16f, head_z = 0.77f, neck_r = 0.085f;
  const float start = -std::acos(neck_r / head_r);
  p.push_back({neck_r, head_z + head_r * std::sin(start), true});
  arc_to(p, 0.f, head_z, head_r, start * 180.f / kPi, 90.f, 20);  // ball head
  const float s = height / (head_z + head_r);
  for (auto& q : p) {
    q.r *= s;
    q.z *= s;
  }
  return revolve("pawn", rings_from_profile(p), segments);
}

Mesh make_builtin(const std::string& shape) {
  if (shape == "pawn") return make_pawn(0.2f);
  if (shape == "sphere") return make_sphere(0.1f);
  if (shape == "box") return make_box(Eigen::Vector3f::Constant(0.2f));
  throw std::invalid_argument("unknown built-in shape '" + shape +
                              "' (expected pawn, sphere or box)");
}

void compute_flat_normals(Mesh& mesh) {
  Mesh flat;
  flat.name = std::move(mesh.name);
  flat.base_colour = mesh.base_colour;
  const std::size_t n = mesh.indices.size() / 3 * 3;
  for (std::size_t t = 0; t < n; t += 3) {
    const std::uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    const Eigen::Vector3f& a = mesh.positions[i[0]];
    Eigen::Vector3f normal = (mesh.positions[i[1]] - a).cross(mesh.positions[i[2]] - a);
    const float length = normal.norm();
    normal = length > 0.f ? Eigen::Vector3f(normal / length) : Eigen::Vector3f::UnitZ();
    for (std::uint32_t v : i) {
      flat.indices.push_back(static_cast<std::uint32_t>(flat.positions.size()));
      flat.positions.push_back(mesh.positions[v]);
      flat.normals.push_back(normal);
      if (!mesh.uvs.empty()) flat.uvs.push_back(mesh.uvs[v]);
      if (!mesh.colours.empty()) flat.colours.push_back(mesh.colours[v]);
    }
  }
  mesh = std::move(flat);
}

namespace detail {

Eigen::Matrix3d model_axes_to_world(const ModelLoadOptions& options) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  if (options.y_up) m << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  return m;
}

void collapse_uniform_colours(Mesh& mesh) {
  if (mesh.colours.empty()) return;
  const Eigen::Vector4f first = mesh.colours.front();
  for (const auto& c : mesh.colours)
    if (c != first) return;
  mesh.base_colour = mesh.base_colour.cwiseProduct(first);
  mesh.colours.clear();
}

}  // namespace detail

Mesh load_model(const std::filesystem::path& path, const ModelLoadOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path, options);
  if (ext == ".obj") return load_obj(path, options);
  throw std::runtime_error(path.string() + ": unknown model format '" + ext +
                           "' (expected .gltf, .glb or .obj)");
}

}  // namespace probeless::render

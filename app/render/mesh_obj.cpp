// Wavefront OBJ through Debian's shared libtinyobjloader (float build). The parser fans
// polygons into triangles and resolves negative (relative) indices; what it lets through
// unchecked (indices past the end, faces of fewer than three corners) is checked here.
#include <tiny_obj_loader.h>

#include <map>
#include <stdexcept>
#include <tuple>

#include "app/render/mesh.hpp"
#include "app/render/model_loading.hpp"

namespace probeless::render {
namespace {

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (auto& c : s)
    if (c == '\n') c = ';';
  return s;
}

}  // namespace

Mesh load_obj(const std::filesystem::path& path, const ModelLoadOptions& options) {
  const std::string file = path.string();
  auto fail = [&](const std::string& what) { throw std::runtime_error(file + ": " + what); };
  detail::check_model_file(path);

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(file, config) || !reader.Error().empty())
    fail("not a readable OBJ file: " + trimmed(reader.Error()));
  // Out-of-range indices are only a warning to tinyobjloader; here they are an error.
  if (reader.Warning().find("out of bounds") != std::string::npos) fail(trimmed(reader.Warning()));

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const auto& materials = reader.GetMaterials();
  // Counts as size_t: an int cast of a count past 2^31 would wrap and let indices through.
  const std::size_t nv = attrib.vertices.size() / 3;
  const std::size_t nn = attrib.normals.size() / 3;
  const std::size_t nt = attrib.texcoords.size() / 2;
  const Eigen::Matrix3f axes = detail::model_axes_to_world(options).cast<float>();

  Mesh mesh;
  mesh.name = path.filename().string();
  bool all_normals = true, any_uv = false;
  // One vertex per distinct (position, normal, texcoord, material) corner.
  std::map<std::tuple<int, int, int, int>, std::uint32_t> vertex_of;
  for (const auto& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    std::size_t offset = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const std::size_t corners = shape.mesh.num_face_vertices[f];
      if (corners != 3)
        fail("shape '" + shape.name + "' face " + std::to_string(f + 1) + " has " +
             std::to_string(corners) + " corners after triangulation (a face needs at least 3)");
      const int material = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
      for (std::size_t c = 0; c < corners; ++c) {
        const tinyobj::index_t& i = idx[offset + c];
        if (i.vertex_index < 0 || static_cast<std::size_t>(i.vertex_index) >= nv ||
            (i.normal_index >= 0 && static_cast<std::size_t>(i.normal_index) >= nn) ||
            (i.texcoord_index >= 0 && static_cast<std::size_t>(i.texcoord_index) >= nt))
          fail("shape '" + shape.name + "' face " + std::to_string(f + 1) +
               " refers to a vertex, normal or texcoord that is not in the file");
        all_normals &= i.normal_index >= 0;
        any_uv |= i.texcoord_index >= 0;
        auto key = std::make_tuple(i.vertex_index, i.normal_index, i.texcoord_index, material);
        // Vertex numbers are 32-bit indices: stop at the limit rather than wrap.
        if (mesh.positions.size() >= static_cast<std::size_t>(read_limits::kMaxModelElements))
          fail("more than " + std::to_string(read_limits::kMaxModelElements) + " vertices");
        auto [it, added] =
            vertex_of.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
        if (added) {
          const float* v = &attrib.vertices[3 * static_cast<std::size_t>(i.vertex_index)];
          mesh.positions.push_back(axes * Eigen::Vector3f(v[0], v[1], v[2]));
          if (i.normal_index >= 0) {
            const float* n = &attrib.normals[3 * static_cast<std::size_t>(i.normal_index)];
            Eigen::Vector3f normal = axes * Eigen::Vector3f(n[0], n[1], n[2]);
            mesh.normals.push_back(normal.norm() > 0 ? normal.normalized() : normal);
          } else {
            mesh.normals.push_back(Eigen::Vector3f::UnitZ());
          }
          if (i.texcoord_index >= 0) {
            const float* t = &attrib.texcoords[2 * static_cast<std::size_t>(i.texcoord_index)];
            mesh.uvs.emplace_back(t[0], t[1]);
          } else {
            mesh.uvs.push_back(Eigen::Vector2f::Zero());
          }
          Eigen::Vector4f colour(1, 1, 1, 1);
          if (material >= 0 && material < static_cast<int>(materials.size())) {
            const auto& m = materials[static_cast<std::size_t>(material)];
            colour << m.diffuse[0], m.diffuse[1], m.diffuse[2], m.dissolve;
          }
          mesh.colours.push_back(colour);
        }
        mesh.indices.push_back(it->second);
      }
      offset += corners;
    }
  }
  if (mesh.indices.empty()) fail("no faces");
  if (!any_uv) mesh.uvs.clear();
  // Without a normal on every corner, shade flat (as glTF does for meshes without normals).
  if (!all_normals) compute_flat_normals(mesh);
  detail::collapse_uniform_colours(mesh);
  try {
    mesh.validate();
  } catch (const std::exception& e) {
    fail(e.what());
  }
  return mesh;
}

}  // namespace probeless::render

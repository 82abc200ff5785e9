#pragma once
// Triangle meshes for virtual objects: built-in shapes made in code and models loaded from
// glTF 2.0 or Wavefront OBJ. Units are metres; the object frame is right-handed with z up
// (the world's convention, core/pose.hpp), so a built-in shape or a loaded model placed with
// an identity rotation stands upright on the floor.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace probeless::render {

// Transfer coefficients per vertex of the PRT material: 5 SH bands.
inline constexpr std::size_t kPrtCoefficients = 25;

struct Mesh {
  std::string name;
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // unit, one per position
  std::vector<Eigen::Vector2f> uvs;      // empty, or one per position
  // Empty, or one linear RGBA per position: set when a model's parts have different base
  // colours (several glTF materials or OBJ usemtl groups); multiplied by base_colour.
  std::vector<Eigen::Vector4f> colours;
  std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
  Eigen::Vector4f base_colour{1.f, 1.f, 1.f, 1.f};  // linear RGBA
  // Empty, or kPrtCoefficients per vertex, vertex after vertex: the PRT transfer vectors
  // (app/render/prt/ bakes them), in the object frame, so that the PrtDiffuse material's exit
  // radiance is albedo * sum_i T_i L_i with L_i the environment's SH radiance turned into the
  // object frame (index l (l + 1) + m, core/sh.hpp). The transfer therefore includes the
  // cosine and the 1/pi of the Lambertian BRDF: an unoccluded vertex with normal n has
  // T_i = A_l Y_i(n) / pi (A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0, A_4 = -pi / 24).
  std::vector<float> prt_transfer;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return indices.size() / 3; }
  // Axis-aligned bounds of the positions (min, max); zero for an empty mesh.
  std::pair<Eigen::Vector3f, Eigen::Vector3f> bounds() const;
  // Throws std::invalid_argument naming `name` when sizes disagree, an index is out of
  // range or a value is not finite.
  void validate() const;
};

// A UV sphere centred on the origin, poles on the z axis.
Mesh make_sphere(float radius, int segments = 48, int rings = 24);
// A box centred on the origin with the given full edge lengths, flat-shaded.
Mesh make_box(const Eigen::Vector3f& size);
// A chess pawn standing on the origin (base at z = 0, top at z = height), a surface of
// revolution about z with creases at the rims: the default virtual object, recognisable at a
// glance and with both convex and concave curvature for the lighting to show.
Mesh make_pawn(float height = 0.2f, int segments = 64);
// Built-in shape by its config name: "pawn", "sphere" (radius 0.1 m), "box" (0.2 m cube).
// Throws std::invalid_argument listing the names for any other.
Mesh make_builtin(const std::string& shape);

// Per-vertex normals from the triangles: each triangle gets its own vertices (flat shading,
// as glTF prescribes for meshes without normals). Colours and uvs are carried along; PRT
// transfer is dropped, since it was baked for the old normals (bake after this).
void compute_flat_normals(Mesh& mesh);

struct ModelLoadOptions {
  // glTF is y-up by definition and OBJ files are y-up by habit; the world here is z-up, so a
  // model is turned +90 degrees about x (y -> z, z -> -y) on load unless this is false.
  bool y_up = true;
};

// glTF 2.0 (.gltf with its buffers, or .glb): every triangle primitive of the default scene
// (or of all root nodes when there is none), node transforms applied, base colour factors
// kept (one colour: base_colour; several: per-vertex colours). Textures are not read.
// Throws std::runtime_error naming the file on any error.
Mesh load_gltf(const std::filesystem::path& path, const ModelLoadOptions& options = {});
// Wavefront OBJ (v, vt, vn, f with polygons fanned into triangles, negative indices; Kd of
// the .mtl materials as colours). Throws std::runtime_error naming the file (and the line
// where the parser gives one).
Mesh load_obj(const std::filesystem::path& path, const ModelLoadOptions& options = {});
// By extension: .gltf/.glb or .obj.
Mesh load_model(const std::filesystem::path& path, const ModelLoadOptions& options = {});

}  // namespace probeless::render

// Built-in shapes and the glTF / OBJ loaders. The model files are written by the tests.
#include "app/render/mesh.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>

#include "support/test_data.hpp"

namespace probeless::render {
namespace {

// Signed volume by the divergence theorem: positive when every triangle runs
// counter-clockwise seen from outside.
double signed_volume(const Mesh& m) {
  double v = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3d a = m.positions[m.indices[t]].cast<double>();
    const Eigen::Vector3d b = m.positions[m.indices[t + 1]].cast<double>();
    const Eigen::Vector3d c = m.positions[m.indices[t + 2]].cast<double>();
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

// Every triangle's winding agrees with its vertex normals.
void expect_windings_match_normals(const Mesh& m) {
  int disagree = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const auto& a = m.positions[m.indices[t]];
    const Eigen::Vector3f n =
        (m.positions[m.indices[t + 1]] - a).cross(m.positions[m.indices[t + 2]] - a);
    if (n.norm() < 1e-12f) continue;
    const Eigen::Vector3f vn =
        m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] + m.normals[m.indices[t + 2]];
    disagree += n.dot(vn) <= 0;
  }
  EXPECT_EQ(disagree, 0) << m.name;
}

TEST(BuiltinMesh, SphereIsClosedOutwardAndRound) {
  const Mesh m = make_sphere(0.5f, 64, 32);
  ASSERT_NO_THROW(m.validate());
  expect_windings_match_normals(m);
  EXPECT_NEAR(signed_volume(m), 4.0 / 3 * std::numbers::pi * 0.125, 0.01);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.positions[i].norm(), 0.5f, 1e-5f);
    EXPECT_TRUE(m.normals[i].isApprox(m.positions[i] / 0.5f, 1e-4f));
  }
}

TEST(BuiltinMesh, BoxHasExactVolumeAndFlatFaces) {
  const Mesh m = make_box({0.2f, 0.4f, 0.6f});
  ASSERT_NO_THROW(m.validate());
  EXPECT_EQ(m.triangle_count(), 12u);
  expect_windings_match_normals(m);
  EXPECT_NEAR(signed_volume(m), 0.2 * 0.4 * 0.6, 1e-6);
  const auto [lo, hi] = m.bounds();
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f(-0.1f, -0.2f, -0.3f)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.3f)));
}

TEST(BuiltinMesh, PawnStandsOnTheOriginAndIsClosed) {
  const Mesh m = make_pawn(0.2f);
  ASSERT_NO_THROW(m.validate());
  expect_windings_match_normals(m);
  const auto [lo, hi] = m.bounds();
  EXPECT_NEAR(lo.z(), 0.f, 1e-6f);
  EXPECT_NEAR(hi.z(), 0.2f, 1e-5f);
  EXPECT_NEAR(hi.x(), -lo.x(), 1e-5f);  // symmetric about z
  EXPECT_GT(hi.x(), 0.06f);             // a base wide enough to stand on
  EXPECT_GT(signed_volume(m), 0.0);
  EXPECT_LT(signed_volume(m), std::numbers::pi * hi.x() * hi.x() * 0.2);
  EXPECT_GT(m.triangle_count(), 2000u);
}

TEST(BuiltinMesh, ByNameAndUnknownName) {
  EXPECT_EQ(make_builtin("pawn").name, "pawn");
  EXPECT_EQ(make_builtin("sphere").name, "sphere");
  EXPECT_EQ(make_builtin("box").name, "box");
  try {
    make_builtin("teapot");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("teapot"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("pawn"), std::string::npos);
  }
}

// --- files written by the tests ---------------------------------------------------------

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

template <typename T>
void append_bytes(std::string& buf, std::initializer_list<T> values) {
  for (T v : values) buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

std::string base64(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v =
        (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], table[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {table[v >> 18], table[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
  }
  return out;
}

std::string triangle_buffer() {
  std::string buf;
  append_bytes<float>(buf, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  append_bytes<std::uint16_t>(buf, {0, 1, 2, 0});
  return buf;
}

// One triangle, (0,0,0) (1,0,0) (0,1,0), under a parent node translated by (1,2,3) and a
// child scaled by 2; base colour (0.2, 0.4, 0.6). `buffer_uri` empty: the GLB binary chunk.
std::string triangle_gltf_json(const std::string& buffer_uri) {
  const std::string buf = triangle_buffer();
  const std::string uri = buffer_uri.empty() ? "" : R"(,"uri":")" + buffer_uri + "\"";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"children":[1],"translation":[1,2,3]},{"mesh":0,"scale":[2,2,2]}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1.0]}}],
    "buffers":[{"byteLength":)" +
         std::to_string(buf.size()) + uri + R"(}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},
                   {"buffer":0,"byteOffset":36,"byteLength":6}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
}

void expect_triangle(const Mesh& m) {
  ASSERT_EQ(m.triangle_count(), 1u);
  ASSERT_EQ(m.vertex_count(), 3u);
  // glTF (x, y, z) -> world (x, -z, y) after the node transforms T(1,2,3) S(2).
  EXPECT_TRUE(m.positions[0].isApprox(Eigen::Vector3f(1, -3, 2)));
  EXPECT_TRUE(m.positions[1].isApprox(Eigen::Vector3f(3, -3, 2)));
  EXPECT_TRUE(m.positions[2].isApprox(Eigen::Vector3f(1, -3, 4)));
  // No normals in the file: flat, from the winding (+z in glTF = -y in the world).
  for (const auto& n : m.normals) EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, -1, 0)));
  EXPECT_TRUE(m.base_colour.isApprox(Eigen::Vector4f(0.2f, 0.4f, 0.6f, 1.f)));
  EXPECT_TRUE(m.colours.empty());
}

TEST(LoadGltf, TriangleWithNodeTransformsAndBaseColour) {
  const auto dir = testing::scratch_dir();
  const std::string json =
      triangle_gltf_json("data:application/octet-stream;base64," + base64(triangle_buffer()));
  write_text(dir / "triangle.gltf", json);
  expect_triangle(load_gltf(dir / "triangle.gltf"));
  expect_triangle(load_model(dir / "triangle.gltf"));

  ModelLoadOptions as_is;
  as_is.y_up = false;
  const Mesh m = load_gltf(dir / "triangle.gltf", as_is);
  EXPECT_TRUE(m.positions[2].isApprox(Eigen::Vector3f(1, 4, 3)));
}

TEST(LoadGltf, BinaryGlbWithExternalFreeBuffer) {
  const auto dir = testing::scratch_dir();
  std::string json = triangle_gltf_json("");
  while (json.size() % 4) json += ' ';
  std::string bin = triangle_buffer();
  while (bin.size() % 4) bin += '\0';
  std::string glb;
  append_bytes<std::uint32_t>(
      glb, {0x46546C67u, 2u, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size())});
  append_bytes<std::uint32_t>(glb, {static_cast<std::uint32_t>(json.size()), 0x4E4F534Au});
  glb += json;
  append_bytes<std::uint32_t>(glb, {static_cast<std::uint32_t>(bin.size()), 0x004E4942u});
  glb += bin;
  write_text(dir / "triangle.glb", glb);
  expect_triangle(load_model(dir / "triangle.glb"));
}

// A cube (8 shared corners, 12 triangles) in two primitives with different materials under
// a node turned 90 degrees about glTF's y (the world's z after the y-up turn), with an
// external .bin buffer.
TEST(LoadGltf, CubeInTwoMaterialsWithRotatedNode) {
  const auto dir = testing::scratch_dir();
  std::string buf;
  append_bytes<float>(
      buf, {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1});
  // Counter-clockwise seen from outside.
  append_bytes<std::uint16_t>(buf, {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5});
  write_text(dir / "cube.bin", buf);
  write_text(dir / "cube.gltf", R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0,"rotation":[0,0.7071067811865476,0,0.7071067811865476]}],
    "meshes":[{"primitives":[
      {"attributes":{"POSITION":0},"indices":1,"material":0},
      {"attributes":{"POSITION":0},"indices":2,"material":1}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}},
                 {"pbrMetallicRoughness":{"baseColorFactor":[0,0,1,1]}}],
    "buffers":[{"byteLength":168,"uri":"cube.bin"}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":96},
                   {"buffer":0,"byteOffset":96,"byteLength":72}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3",
                  "min":[-1,-1,-1],"max":[1,1,1]},
                 {"bufferView":1,"byteOffset":0,"componentType":5123,"count":18,"type":"SCALAR"},
                 {"bufferView":1,"byteOffset":36,"componentType":5123,"count":18,"type":"SCALAR"}]})");
  const Mesh m = load_gltf(dir / "cube.gltf");
  EXPECT_EQ(m.triangle_count(), 12u);
  EXPECT_EQ(m.vertex_count(), 36u);  // flat normals: three corners per triangle
  EXPECT_NEAR(signed_volume(m), 8.0, 1e-4);
  expect_windings_match_normals(m);
  ASSERT_EQ(m.colours.size(), 36u);
  int red = 0, blue = 0;
  for (const auto& c : m.colours) {
    red += c.isApprox(Eigen::Vector4f(1, 0, 0, 1));
    blue += c.isApprox(Eigen::Vector4f(0, 0, 1, 1));
  }
  EXPECT_EQ(red, 18);
  EXPECT_EQ(blue, 18);
  // glTF's first primitive holds the faces z = -1 and z = +1 (glTF axes) and y = -1. Turned
  // about glTF y by 90 degrees, glTF z -> glTF x; then y-up -> z-up leaves x as x.
  for (std::size_t i = 0; i < 18; ++i) {
    const Eigen::Vector3f n = m.normals[i];
    EXPECT_TRUE(std::abs(n.x()) > 0.99f || n.z() < -0.99f) << n.transpose();
  }
}

void expect_error_names_file(const std::function<void()>& load, const std::filesystem::path& file,
                             const std::string& also = "") {
  try {
    load();
    ADD_FAILURE() << "no error for " << file;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    if (!also.empty()) {
      EXPECT_NE(what.find(also), std::string::npos) << what;
    }
  }
}

// make fuzz's finding (tests/fuzz/corpus/gltf/crash-tinygltf-out-of-range.glb, 712 bytes): a
// GLB on which tinygltf throws std::out_of_range from its own parser instead of returning
// false; it reached std::terminate through `probeless run`.
TEST(LoadGltf, TinygltfsOwnExceptionsAreAClearError) {
  const auto finding = std::filesystem::path(PROBELESS_TEST_SOURCE_DIR) /
                       "../../fuzz/corpus/gltf/crash-tinygltf-out-of-range.glb";
  const auto file = testing::scratch_dir() / "finding.glb";
  std::filesystem::copy_file(finding, file, std::filesystem::copy_options::overwrite_existing);
  expect_error_names_file([&] { load_gltf(file); }, file, "not a readable glTF file");
}

TEST(LoadGltf, MalformedFilesNameTheFile) {
  const auto dir = testing::scratch_dir();
  write_text(dir / "broken.gltf", "{ \"asset\": { \"version\": \"2.0\" }, ");
  expect_error_names_file([&] { load_gltf(dir / "broken.gltf"); }, dir / "broken.gltf");

  std::string buf = triangle_buffer();
  buf[36] = 7;  // first index points past the three vertices
  write_text(dir / "bad_index.gltf",
             triangle_gltf_json("data:application/octet-stream;base64," + base64(buf)));
  expect_error_names_file([&] { load_gltf(dir / "bad_index.gltf"); }, dir / "bad_index.gltf",
                          "index 7");

  write_text(dir / "empty.gltf", R"({"asset":{"version":"2.0"}})");
  expect_error_names_file([&] { load_gltf(dir / "empty.gltf"); }, dir / "empty.gltf",
                          "no triangle");
  expect_error_names_file([&] { load_gltf(dir / "missing.gltf"); }, dir / "missing.gltf");
  expect_error_names_file([&] { load_model(dir / "model.stl"); }, dir / "model.stl", ".stl");
}

// A unit cube as six quads, one written with negative (relative) indices, and a .mtl colour.
TEST(LoadObj, QuadsNegativeIndicesAndMaterialColour) {
  const auto dir = testing::scratch_dir();
  write_text(dir / "cube.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
  write_text(dir / "cube.obj", R"(# cube, y up
mtllib cube.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
usemtl red
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f -5 -1 -2 -6
f 1 5 8 4
f 2 3 7 6
)");
  const Mesh m = load_obj(dir / "cube.obj");
  EXPECT_EQ(m.triangle_count(), 12u);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-5);
  expect_windings_match_normals(m);
  EXPECT_TRUE(m.base_colour.isApprox(Eigen::Vector4f(0.8f, 0.1f, 0.1f, 1.f)));
  EXPECT_TRUE(m.colours.empty());
  // y up in the file -> z up in the world: the file's y = 1 top is at z = 1.
  const auto [lo, hi] = m.bounds();
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f(0, -1, 0)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(1, 0, 1)));
}

TEST(LoadObj, NormalsFromTheFileAndPolygonFans) {
  const auto dir = testing::scratch_dir();
  write_text(dir / "pentagon.obj", R"(v 0 0 0
v 2 0 0
v 3 1 0
v 1 2 0
v -1 1 0
vn 0 0 1
f 1//1 2//1 3//1 4//1 5//1
)");
  ModelLoadOptions as_is;
  as_is.y_up = false;
  const Mesh m = load_obj(dir / "pentagon.obj", as_is);
  EXPECT_EQ(m.triangle_count(), 3u);
  EXPECT_EQ(m.vertex_count(), 5u);
  for (const auto& n : m.normals) EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, 0, 1)));
  const Mesh turned = load_obj(dir / "pentagon.obj");
  for (const auto& n : turned.normals) EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, -1, 0)));
}

TEST(LoadObj, MalformedFilesNameTheFile) {
  const auto dir = testing::scratch_dir();
  write_text(dir / "out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expect_error_names_file([&] { load_obj(dir / "out_of_range.obj"); }, dir / "out_of_range.obj");
  write_text(dir / "zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expect_error_names_file([&] { load_obj(dir / "zero_index.obj"); }, dir / "zero_index.obj",
                          "line 4");
  write_text(dir / "no_faces.obj", "v 0 0 0\nv 1 0 0\n");
  expect_error_names_file([&] { load_obj(dir / "no_faces.obj"); }, dir / "no_faces.obj",
                          "no faces");
  expect_error_names_file([&] { load_obj(dir / "missing.obj"); }, dir / "missing.obj");
}

}  // namespace
}  // namespace probeless::render

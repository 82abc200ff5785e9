// glTF 2.0 through Debian's shared libtinygltf (it carries the implementation, so no
// TINYGLTF_IMPLEMENTATION here).
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <new>
#include <set>
#include <stdexcept>

#include "app/render/mesh.hpp"
#include "app/render/model_loading.hpp"
#include "core/read_limits.hpp"

namespace probeless::render {
namespace {

struct GltfError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads accessor `index` as `width` doubles per element, converting integer components
// (normalised ones to [0,1]). Bounds are checked against the buffer view and the buffer.
std::vector<double> read_accessor(const tinygltf::Model& model, int index, int width,
                                  const char* what) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size()))
    throw GltfError(std::string(what) + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
  const std::string name = std::string(what) + " (accessor " + std::to_string(index) + ")";
  if (acc.sparse.isSparse) throw GltfError(name + ": sparse accessors are not supported");
  const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
  if (components != width && !(width == 4 && components == 3))
    throw GltfError(name + ": has " + std::to_string(components) + " components, expected " +
                    std::to_string(width));
  // Every size below is the file's claim: checked without overflow before anything is
  // allocated (a count near 2^64 / 3 used to wrap the bounds check and crash).
  if (acc.count > static_cast<std::size_t>(read_limits::kMaxModelElements))
    throw GltfError(name + ": count " + std::to_string(acc.count) + " is over the limit of " +
                    std::to_string(read_limits::kMaxModelElements));
  const std::size_t values = acc.count * static_cast<std::size_t>(width);
  if (acc.bufferView < 0)  // all zeros by the spec (alpha stays 1)
    return std::vector<double>(values, width == 4 ? 1.0 : 0.0);
  if (acc.bufferView >= static_cast<int>(model.bufferViews.size()))
    throw GltfError(name + ": buffer view " + std::to_string(acc.bufferView) + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
    throw GltfError(name + ": buffer " + std::to_string(view.buffer) + " does not exist");
  const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
  const int stride = acc.ByteStride(view);
  const int component_size =
      tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType));
  if (stride <= 0 || component_size <= 0) throw GltfError(name + ": invalid stride or type");
  if (acc.count == 0) return {};
  // The view lies in the buffer and the accessor's elements in the view. With count bounded
  // above, stride * (count - 1) + element fits in 64 bits; the offsets are compared by
  // subtraction so that no sum of the file's numbers can wrap.
  const std::size_t element = static_cast<std::size_t>(component_size) * components;
  const std::size_t span = static_cast<std::size_t>(stride) * (acc.count - 1) + element;
  if (view.byteOffset > buffer.data.size() ||
      view.byteLength > buffer.data.size() - view.byteOffset || acc.byteOffset > view.byteLength ||
      span > view.byteLength - acc.byteOffset)
    throw GltfError(name + ": " + std::to_string(acc.count) + " elements at byte " +
                    std::to_string(acc.byteOffset) + " read past the end of its buffer view (" +
                    std::to_string(view.byteLength) + " bytes)");
  std::vector<double> out(values, width == 4 ? 1.0 : 0.0);
  const unsigned char* base = buffer.data.data() + view.byteOffset + acc.byteOffset;
  for (std::size_t i = 0; i < acc.count; ++i) {
    const unsigned char* e = base + i * static_cast<std::size_t>(stride);
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = e + static_cast<std::size_t>(c) * component_size;
      double v = 0;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
          float f;
          std::memcpy(&f, p, 4);
          v = f;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          v = *p / (acc.normalized ? 255.0 : 1.0);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          v = s / (acc.normalized ? 65535.0 : 1.0);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
          std::uint32_t u;
          std::memcpy(&u, p, 4);
          v = u;
          break;
        }
        default:
          throw GltfError(name + ": component type " + std::to_string(acc.componentType) +
                          " is not supported here");
      }
      out[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)] = v;
    }
  }
  return out;
}

Eigen::Matrix4d local_transform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return Eigen::Map<const Eigen::Matrix4d>(node.matrix.data());
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3)
    t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    t.rotate(
        Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])
            .normalized());
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

// Triangle list of one primitive as indices into its vertices.
std::vector<std::uint32_t> triangles(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                     std::size_t vertex_count) {
  std::vector<std::uint32_t> idx;
  if (prim.indices >= 0) {
    for (double v : read_accessor(model, prim.indices, 1, "indices")) {
      if (v >= static_cast<double>(vertex_count))
        throw GltfError("index " + std::to_string(static_cast<long long>(v)) + " >= vertex count " +
                        std::to_string(vertex_count));
      idx.push_back(static_cast<std::uint32_t>(v));
    }
  } else {
    for (std::size_t i = 0; i < vertex_count; ++i) idx.push_back(static_cast<std::uint32_t>(i));
  }
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    idx.resize(idx.size() / 3 * 3);
    return idx;
  }
  std::vector<std::uint32_t> out;
  for (std::size_t i = 2; i < idx.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      if (i % 2 == 0)
        out.insert(out.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else
        out.insert(out.end(), {idx[i - 1], idx[i - 2], idx[i]});
    } else {  // TRIANGLE_FAN
      out.insert(out.end(), {idx[0], idx[i - 1], idx[i]});
    }
  }
  return out;
}

class Loader {
 public:
  Loader(const tinygltf::Model& model, const ModelLoadOptions& options)
      : model_(model), axes_(detail::model_axes_to_world(options)) {}

  Mesh run() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (s >= static_cast<int>(model_.scenes.size()))
        throw GltfError("default scene " + std::to_string(s) + " does not exist");
      roots = model_.scenes[static_cast<std::size_t>(s)].nodes;
    } else {
      std::set<int> children;
      for (const auto& n : model_.nodes) children.insert(n.children.begin(), n.children.end());
      for (int i = 0; i < static_cast<int>(model_.nodes.size()); ++i)
        if (!children.count(i)) roots.push_back(i);
    }
    Eigen::Matrix4d root = Eigen::Matrix4d::Identity();
    root.topLeftCorner<3, 3>() = axes_;
    for (int r : roots) visit(r, root, 0);
    if (mesh_.indices.empty()) throw GltfError("no triangle primitives in the scene");
    detail::collapse_uniform_colours(mesh_);
    if (!has_uvs_) mesh_.uvs.clear();
    return std::move(mesh_);
  }

 private:
  void visit(int index, const Eigen::Matrix4d& parent, int depth) {
    if (index < 0 || index >= static_cast<int>(model_.nodes.size()))
      throw GltfError("node " + std::to_string(index) + " does not exist");
    if (depth > 64) throw GltfError("node hierarchy deeper than 64 (a cycle?)");
    const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(index)];
    const Eigen::Matrix4d world = parent * local_transform(node);
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(model_.meshes.size()))
        throw GltfError("mesh " + std::to_string(node.mesh) + " does not exist");
      for (const auto& prim : model_.meshes[static_cast<std::size_t>(node.mesh)].primitives)
        add_primitive(prim, world);
    }
    for (int child : node.children) visit(child, world, depth + 1);
  }

  void add_primitive(const tinygltf::Primitive& prim, const Eigen::Matrix4d& world) {
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN)
      return;  // points and lines have no surface to shade
    auto attribute = [&](const char* key) {
      auto it = prim.attributes.find(key);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    if (attribute("POSITION") < 0) throw GltfError("a primitive has no POSITION");
    Mesh part;
    const auto pos = read_accessor(model_, attribute("POSITION"), 3, "POSITION");
    const std::size_t n = pos.size() / 3;
    for (std::size_t i = 0; i < n; ++i)
      part.positions.emplace_back(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    if (attribute("NORMAL") >= 0) {
      const auto nrm = read_accessor(model_, attribute("NORMAL"), 3, "NORMAL");
      if (nrm.size() != pos.size()) throw GltfError("NORMAL and POSITION differ in count");
      for (std::size_t i = 0; i < n; ++i)
        part.normals.emplace_back(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    }
    if (attribute("TEXCOORD_0") >= 0) {
      const auto uv = read_accessor(model_, attribute("TEXCOORD_0"), 2, "TEXCOORD_0");
      if (uv.size() / 2 != n) throw GltfError("TEXCOORD_0 and POSITION differ in count");
      for (std::size_t i = 0; i < n; ++i) part.uvs.emplace_back(uv[2 * i], uv[2 * i + 1]);
      has_uvs_ = true;
    } else {
      part.uvs.assign(n, Eigen::Vector2f::Zero());
    }
    Eigen::Vector4f factor(1, 1, 1, 1);
    if (prim.material >= 0) {
      if (prim.material >= static_cast<int>(model_.materials.size()))
        throw GltfError("material " + std::to_string(prim.material) + " does not exist");
      const auto& f = model_.materials[static_cast<std::size_t>(prim.material)]
                          .pbrMetallicRoughness.baseColorFactor;
      if (f.size() == 4) factor = Eigen::Vector4d(f[0], f[1], f[2], f[3]).cast<float>();
    }
    part.colours.assign(n, factor);
    if (attribute("COLOR_0") >= 0) {
      const auto col = read_accessor(model_, attribute("COLOR_0"), 4, "COLOR_0");
      if (col.size() / 4 != n) throw GltfError("COLOR_0 and POSITION differ in count");
      for (std::size_t i = 0; i < n; ++i)
        part.colours[i] = factor.cwiseProduct(
            Eigen::Vector4d(col[4 * i], col[4 * i + 1], col[4 * i + 2], col[4 * i + 3])
                .cast<float>());
    }
    part.indices = triangles(model_, prim, n);
    if (part.normals.empty()) compute_flat_normals(part);
    append(part, world);
  }

  void append(const Mesh& part, const Eigen::Matrix4d& world) {
    const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
    const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
    const bool mirrored = linear.determinant() < 0;
    const auto base = static_cast<std::uint32_t>(mesh_.positions.size());
    for (std::size_t i = 0; i < part.positions.size(); ++i) {
      const Eigen::Vector3d p =
          linear * part.positions[i].cast<double>() + world.topRightCorner<3, 1>();
      mesh_.positions.push_back(p.cast<float>());
      Eigen::Vector3d nrm = normal_matrix * part.normals[i].cast<double>();
      mesh_.normals.push_back(nrm.norm() > 0 ? Eigen::Vector3f(nrm.normalized().cast<float>())
                                             : Eigen::Vector3f::UnitZ());
      mesh_.uvs.push_back(part.uvs[i]);
      mesh_.colours.push_back(part.colours[i]);
    }
    for (std::size_t t = 0; t + 2 < part.indices.size(); t += 3) {
      const std::uint32_t a = part.indices[t], b = part.indices[t + 1], c = part.indices[t + 2];
      if (mirrored)
        mesh_.indices.insert(mesh_.indices.end(), {base + a, base + c, base + b});
      else
        mesh_.indices.insert(mesh_.indices.end(), {base + a, base + b, base + c});
    }
  }

  const tinygltf::Model& model_;
  Eigen::Matrix3d axes_;
  bool has_uvs_ = false;
  Mesh mesh_;
};

// Textures are not used yet: skip decoding them (and failing on formats stb cannot read).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

}  // namespace

Mesh load_gltf(const std::filesystem::path& path, const ModelLoadOptions& options) {
  const std::string file = path.string();
  tinygltf::Model model;
  tinygltf::TinyGLTF reader;
  reader.SetImageLoader(skip_image, nullptr);
  std::string err, warn;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  detail::check_model_file(path);
  bool ok = false;
  try {
    ok = ext == ".glb" ? reader.LoadBinaryFromFile(&model, &err, &warn, file)
                       : reader.LoadASCIIFromFile(&model, &err, &warn, file);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    // tinygltf 2.5 itself throws on some malformed files (std::out_of_range from a
    // vector::at over an empty buffer list: make fuzz, tests/fuzz/corpus/gltf/crash-*).
    err = e.what();
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw std::runtime_error(
        file + ": not a readable glTF file: " + (err.empty() ? std::string("unknown error") : err));
  }
  try {
    Mesh mesh = Loader(model, options).run();
    mesh.name = path.filename().string();
    mesh.validate();
    return mesh;
  } catch (const std::exception& e) {
    throw std::runtime_error(file + ": " + e.what());
  }
}

}  // namespace probeless::render

#include "app/pipeline/scene_objects.hpp"

#include <algorithm>
#include <numbers>

#include "app/render/prt/prt.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless {
namespace {

using Shading = render::Material::Shading;

Shading shading_of(const std::string& material) {
  if (material == "mirror") return Shading::Mirror;
  if (material == "metal") return Shading::RoughMetal;
  if (material == "glass") return Shading::Refraction;
  if (material == "diffuse") return Shading::ShDiffuse;
  if (material == "prt") return Shading::PrtDiffuse;
  return Shading::Lambert;
}

// All objects as one mesh in the world frame: the ground's shadow is everything's together.
render::Mesh world_mesh(const std::vector<render::VirtualObject>& objects) {
  render::Mesh all;
  all.name = "scene";
  for (const auto& o : objects) {
    const auto base = static_cast<std::uint32_t>(all.positions.size());
    const Eigen::Matrix3f r = o.T_world_object.rotation.toRotationMatrix().cast<float>();
    const Eigen::Vector3f t = o.T_world_object.translation.cast<float>();
    const auto s = static_cast<float>(o.scale);
    for (std::size_t i = 0; i < o.mesh->positions.size(); ++i) {
      all.positions.push_back(r * (s * o.mesh->positions[i]) + t);
      all.normals.push_back(r * o.mesh->normals[i]);
    }
    for (std::uint32_t index : o.mesh->indices) all.indices.push_back(base + index);
  }
  return all;
}

// What each triangle of world_mesh(objects) does to a shadow ray: mirror and metal objects
// reflect it on with their colour's mean as reflectance (thesis ch. 6: a mirror's shadow is
// not too dark; a rough metal's lobe is narrow enough that the mirror direction stands in for
// it), every other material blocks it (0). Empty when nothing reflects: the plain shadow bake.
std::vector<float> shadow_reflectance(const std::vector<render::VirtualObject>& objects) {
  std::vector<float> out;
  bool any = false;
  for (const auto& o : objects) {
    const auto s = o.material.shading;
    const bool reflects = s == Shading::Mirror || s == Shading::RoughMetal;
    const auto& c = o.material.base_colour;
    const float r = reflects ? std::clamp((c[0] + c[1] + c[2]) / 3.f, 0.f, 1.f) : 0.f;
    any = any || r > 0.f;
    out.insert(out.end(), o.mesh->triangle_count(), r);
  }
  if (!any) out.clear();
  return out;
}

}  // namespace

Eigen::Vector3d default_object_anchor() {
  return {0.0, 0.6, 0.75};
}

Eigen::Vector3d object_position(const ObjectConfig& object, const RigScene& scene) {
  if (object.position) return *object.position;
  return scene.object_anchor.value_or(default_object_anchor()) + object.anchor_offset;
}

void place_objects(std::vector<ObjectConfig>& objects, const RigScene& scene) {
  for (ObjectConfig& o : objects) o.position = object_position(o, scene);
}

std::filesystem::path default_prt_cache_dir() {
  const std::filesystem::path opencl = default_program_cache_dir();
  return opencl.empty() ? opencl : opencl.parent_path() / "prt";
}

std::vector<render::VirtualObject> make_scene_objects(const std::vector<ObjectConfig>& objects,
                                                      const GroundConfig& ground,
                                                      const std::filesystem::path& prt_cache_dir) {
  prt::BakeOptions bake;
  bake.cache_dir = prt_cache_dir;
  std::vector<render::VirtualObject> out;
  bool image_based = false;
  double lowest = std::numeric_limits<double>::infinity();
  for (const ObjectConfig& c : objects) {
    auto mesh = std::make_shared<render::Mesh>(c.model.empty() ? render::make_builtin(c.shape)
                                                               : render::load_model(c.model));
    const float bottom = mesh->bounds().first.z();
    render::VirtualObject o;
    o.scale = c.scale;
    o.material.shading = shading_of(c.material);
    o.material.base_colour = {c.colour.x(), c.colour.y(), c.colour.z(), 1.f};
    o.material.roughness = static_cast<float>(c.roughness);
    o.material.ior = static_cast<float>(c.ior);
    o.T_world_object.rotation =
        Eigen::AngleAxisd(c.yaw_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d base = object_position(c, RigScene{});
    o.T_world_object.translation = base - Eigen::Vector3d(0, 0, bottom * c.scale);
    lowest = std::min(lowest, base.z());
    if (o.material.shading == Shading::PrtDiffuse) {
      // The table under the object blocks the light from below (in the object frame: the
      // plane through its lowest point; the yaw keeps it level).
      prt::Scene scene;
      scene.ground =
          prt::Ground{prt::Plane{Eigen::Vector3f(0, 0, bottom), Eigen::Vector3f::UnitZ()}};
      const prt::Bake b = prt::bake_prt(*mesh, scene, bake);
      mesh->prt_transfer = b.object.coefficients;
    }
    image_based = image_based || o.material.shading != Shading::Lambert;
    o.mesh = std::move(mesh);
    out.push_back(std::move(o));
  }
  if (ground.enabled && image_based && !out.empty()) {
    const render::Mesh all = world_mesh(out);
    prt::Scene scene;
    prt::Ground g;
    g.plane.point = Eigen::Vector3f(0, 0, static_cast<float>(ground.height_m.value_or(lowest)));
    g.side = static_cast<float>(ground.size_m);
    scene.ground = g;
    scene.triangle_reflectance = shadow_reflectance(out);
    const prt::Bake b = prt::bake_prt(all, scene, bake);
    auto grid = std::make_shared<render::Mesh>(b.ground);
    grid->name = "ground";
    grid->prt_transfer = b.ground_difference().coefficients;
    render::VirtualObject receiver;
    receiver.mesh = std::move(grid);
    receiver.material.shading = Shading::GroundShadow;
    receiver.material.base_colour = {ground.albedo.x(), ground.albedo.y(), ground.albedo.z(), 1.f};
    receiver.material.depth_offset_mm = 50.f;
    out.push_back(std::move(receiver));
  }
  return out;
}

std::vector<render::VirtualObject> placeholder_objects(
    const std::vector<render::VirtualObject>& objects) {
  std::vector<render::VirtualObject> out;
  for (render::VirtualObject o : objects) {
    if (o.material.shading == Shading::GroundShadow) continue;
    o.material.shading = Shading::Lambert;
    o.environment.reset();
    out.push_back(std::move(o));
  }
  return out;
}

render::RendererConfig renderer_config_for(const std::vector<render::VirtualObject>& objects) {
  render::RendererConfig config;
  const bool rough = std::any_of(objects.begin(), objects.end(), [](const auto& o) {
    return o.material.shading == render::Material::Shading::RoughMetal;
  });
  if (!rough) config.prefilter.levels = 1;
  return config;
}

}  // namespace probeless

#include "app/pipeline/scene_objects.hpp"

#include <numbers>

#include "drivers/sim/sim_rig.hpp"

namespace probeless {

std::vector<render::VirtualObject> make_scene_objects(const std::vector<ObjectConfig>& objects) {
  std::vector<render::VirtualObject> out;
  for (const ObjectConfig& c : objects) {
    auto mesh = std::make_shared<render::Mesh>(c.model.empty() ? render::make_builtin(c.shape)
                                                               : render::load_model(c.model));
    const float bottom = mesh->bounds().first.z();
    render::VirtualObject o;
    o.mesh = std::move(mesh);
    o.scale = c.scale;
    o.material.base_colour = {c.color.x(), c.color.y(), c.color.z(), 1.f};
    o.T_world_object.rotation =
        Eigen::AngleAxisd(c.yaw_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d base = c.position.value_or(sim::object_anchor());
    o.T_world_object.translation = base - Eigen::Vector3d(0, 0, bottom * c.scale);
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace probeless

#pragma once
#include <vector>

#include "app/pipeline/service_config.hpp"
#include "app/render/renderer.hpp"

namespace probeless {

// Virtual objects from config: meshes built or loaded once, placed in the world frame. An
// object's `position` is where its lowest point stands (so a sphere rests on the table rather
// than sinking into it); without one it stands on the synthetic rig's table anchor.
std::vector<render::VirtualObject> make_scene_objects(const std::vector<ObjectConfig>& objects);

}  // namespace probeless

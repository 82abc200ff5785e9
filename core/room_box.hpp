#pragma once
// A room proxy for parallax (docs/light-capture.md "Parallax"): an axis-aligned box in world
// coordinates (metres) standing for the room's walls, floor and ceiling, as the box-projected
// reflection probes of game engines use. A rig may know its room (RigScene, the sim's); the
// light stages (kernels/envmap, kernels/light) take it to reproject keyframe texels.
#include <Eigen/Core>

namespace probeless {

struct RoomBox {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
};

}  // namespace probeless

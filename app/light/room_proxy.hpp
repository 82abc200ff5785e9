#pragma once
// Room proxies for the light capture's parallax (docs/light-capture.md "Parallax"): the sim's
// room as an envmap::RoomBox, taken from drivers/sim's own geometry so that the numbers live
// in one place.
#include "kernels/envmap/envmap_types.hpp"

namespace probeless::light {

envmap::RoomBox sim_room_box();

}  // namespace probeless::light

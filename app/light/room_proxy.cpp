#include "app/light/room_proxy.hpp"

#include "drivers/sim/sim_rig.hpp"

namespace probeless::light {

envmap::RoomBox sim_room_box() {
  const auto [lo, hi] = sim::room_bounds();
  return {lo, hi};
}

}  // namespace probeless::light

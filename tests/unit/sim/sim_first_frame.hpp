#pragma once
// The first RGB-D frame of a sim built from `spec` (parse_sim_options): the sim tests that
// look at one frame of a scene.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "drivers/sim/sim_rig.hpp"

namespace probeless::sim {

inline RgbdFrame first_frame(const std::string& spec) {
  Rig rig = make_sim_rig(parse_sim_options(spec));
  RgbdFrame f;
  EXPECT_EQ(rig.rgbd->read(f, std::chrono::milliseconds(10000)), ReadResult::Frame);
  return f;
}

}  // namespace probeless::sim

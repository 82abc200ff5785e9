// `stamp=1` on the sim: each RGB-D frame carries its own timestamp as a capture stamp, live and
// prerendered, and off by default the picture is untouched.
#include <gtest/gtest.h>

#include "core/capture_stamp.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless::sim {
namespace {

using namespace std::chrono_literals;

TEST(SimStamp, EachFrameCarriesItsTimestamp) {
  for (const char* spec :
       {"realtime=0,truth=0,stamp=1", "realtime=1,truth=0,stamp=1,prerender=2"}) {
    SCOPED_TRACE(spec);
    Rig rig = make_sim_rig(parse_sim_options(spec));
    for (int i = 0; i < 3; ++i) {
      RgbdFrame f;
      ASSERT_EQ(rig.rgbd->read(f, 10'000ms), ReadResult::Frame);
      const StampReading r = read_capture_stamp(f.colour);
      ASSERT_EQ(r.result, StampRead::Ok) << to_string(r.result);
      EXPECT_EQ(unwrap_stamp(r.micros, monotonic_now_ns()), f.timestamp_ns / 1000 * 1000);
    }
  }
  EXPECT_FALSE(parse_sim_options("").stamp);
  Rig plain = make_sim_rig(parse_sim_options("realtime=0,truth=0"));
  RgbdFrame f;
  ASSERT_EQ(plain.rgbd->read(f, 10'000ms), ReadResult::Frame);
  EXPECT_NE(read_capture_stamp(f.colour).result, StampRead::Ok);
}

}  // namespace
}  // namespace probeless::sim

#include "app/pipeline/service_config.hpp"

#include <gtest/gtest.h>

#include "app/pipeline/frame_processor.hpp"
#include "app/pipeline/light_capture.hpp"
#include "app/pipeline/scene_objects.hpp"
#include "core/error.hpp"
#include "drivers/sim/sim_rig.hpp"

namespace probeless {
namespace {

TEST(ServiceConfig, EmptyTextGivesTheBuiltInDefault) {
  const ServiceConfig c = parse_service_config("");
  EXPECT_EQ(c.source, "sim");
  // Issue #6's demo: a mirror sphere and a self-shadowed pawn on the table, and its ground.
  ASSERT_EQ(c.objects.size(), 2u);
  EXPECT_EQ(c.objects[0].shape, "sphere");
  EXPECT_EQ(c.objects[0].material, "mirror");
  EXPECT_EQ(c.objects[1].shape, "pawn");
  EXPECT_EQ(c.objects[1].material, "prt");
  EXPECT_TRUE(c.ground.enabled);
  EXPECT_EQ(c.http.address, "127.0.0.1");
  EXPECT_EQ(c.http.port, 8080);
}

TEST(ServiceConfig, ReadsEverySection) {
  const ServiceConfig c = parse_service_config(R"(
[source]
rig = "replay:/data/rec1"
[[object]]
shape = "sphere"
position = [1.0, 2.0, 0.75]
scale = 0.1
color = [0.9, 0.9, 0.9]
material = "metal"
roughness = 0.6
[[object]]
model = "duck.gltf"
material = "glass"
ior = 1.33
[ground]
height_m = 0.7
size_m = 1.5
albedo = [0.5, 0.4, 0.3]
[occlusion]
method = "direct2"
[http]
address = "0.0.0.0"
port = 9000
[output]
dir = "/tmp/out"
format = "png"
matte = true
[pipeline]
frames = 42
[bracket]
mains_hz = 60
max_gain_db = 12
initial_exposure_ms = 2.5
gpio_chip = "gpiochip1"
gpio_line = 17
[light]
face_size = 64
keyframe_distance_m = 0.25
max_keyframes = 9
room = "box"
room_min = [-2.0, -3.0, 0.0]
room_max = [2.5, 3.0, 2.4]
)");
  EXPECT_EQ(c.source, "replay:/data/rec1");
  ASSERT_EQ(c.objects.size(), 2u);
  EXPECT_EQ(c.objects[0].shape, "sphere");
  ASSERT_TRUE(c.objects[0].position.has_value());
  EXPECT_DOUBLE_EQ(c.objects[0].position->z(), 0.75);
  EXPECT_DOUBLE_EQ(c.objects[0].scale, 0.1);
  EXPECT_EQ(c.objects[0].material, "metal");
  EXPECT_DOUBLE_EQ(c.objects[0].roughness, 0.6);
  EXPECT_FALSE(c.objects[0].position == std::nullopt);
  EXPECT_EQ(c.objects[1].model, "duck.gltf");
  EXPECT_EQ(c.objects[1].material, "glass");
  EXPECT_DOUBLE_EQ(c.objects[1].ior, 1.33);
  EXPECT_FALSE(c.objects[1].position.has_value());  // the table anchor, at scene building
  ASSERT_TRUE(c.ground.height_m.has_value());
  EXPECT_DOUBLE_EQ(*c.ground.height_m, 0.7);
  EXPECT_DOUBLE_EQ(c.ground.size_m, 1.5);
  EXPECT_FLOAT_EQ(c.ground.albedo.x(), 0.5f);
  EXPECT_EQ(c.occlusion_method, "direct2");
  EXPECT_EQ(c.http.port, 9000);
  EXPECT_EQ(c.files.format, ImageFileFormat::Png);
  EXPECT_TRUE(c.files.write_matte);
  EXPECT_EQ(c.max_frames, 42);
  EXPECT_TRUE(c.bracket_enabled);
  EXPECT_EQ(c.bracket.mains_hz, 60);
  EXPECT_EQ(c.bracket.max_gain_db, 12);
  EXPECT_DOUBLE_EQ(c.bracket.initial_exposure, 0.0025);
  EXPECT_EQ(c.trigger_chip, "gpiochip1");
  EXPECT_EQ(c.trigger_line, 17);
  EXPECT_TRUE(c.light_enabled);
  EXPECT_EQ(c.light_face_size, 64);
  EXPECT_EQ(c.light_keyframe_distance_m, 0.25);
  EXPECT_EQ(c.light_max_keyframes, 9);
  EXPECT_EQ(ServiceConfig{}.light_max_keyframes, 16);  // the default within the memory budget
  EXPECT_EQ(c.light_room, "box");
  EXPECT_DOUBLE_EQ(c.light_room_min.y(), -3.0);
  EXPECT_DOUBLE_EQ(c.light_room_max.z(), 2.4);
}

// The admin's switch for the hole cores (docs/occlusion.md "Occluders the sensor cannot see"):
// on by default, off gives the shipped CVF without them, and it must be a boolean.
TEST(ServiceConfig, NearOccludersSwitchesTheHoleCores) {
  const ServiceConfig on = parse_service_config("");
  EXPECT_TRUE(on.occlusion_near_occluders);
  EXPECT_EQ(occlusion_params(on).cvf.hole_core_px, occlusion::CvfLocalParams{}.hole_core_px);
  EXPECT_GT(occlusion_params(on).cvf.hole_core_px, 0);
  const ServiceConfig off = parse_service_config("[occlusion]\nnear_occluders = false\n");
  EXPECT_FALSE(off.occlusion_near_occluders);
  EXPECT_EQ(occlusion_params(off).cvf.hole_core_px, 0);
  EXPECT_EQ(off.occlusion_method, "cvf");
  EXPECT_THROW(parse_service_config("[occlusion]\nnear_occluders = \"no\"\n"), ParseError);
}

// The sensor's range for its beyond-range holes (core/beyond_range.hpp): on by default at
// the rule's own default, 0 turns it off, and nonsense is an error naming the key.
TEST(ServiceConfig, BeyondRangeSetsTheFarHoleRule) {
  EXPECT_EQ(beyond_range_rule(parse_service_config("")).far_mm, BeyondRangeRule{}.far_mm);
  EXPECT_GT(BeyondRangeRule{}.far_mm, 0);
  EXPECT_EQ(beyond_range_rule(parse_service_config("[occlusion]\nbeyond_range_m = 7.5\n")).far_mm,
            7500);
  EXPECT_EQ(beyond_range_rule(parse_service_config("[occlusion]\nbeyond_range_m = 0\n")).far_mm, 0);
  for (const char* bad : {"-1", "0.2", "25", "\"far\""})
    EXPECT_THROW(parse_service_config(std::string("[occlusion]\nbeyond_range_m = ") + bad + "\n"),
                 ParseError)
        << bad;
}

TEST(ServiceConfig, LightUpdateRateIsCappedOrEveryFrame) {
  EXPECT_EQ(ServiceConfig{}.light_update_hz, 25);
  EXPECT_EQ(parse_service_config("[light]\nupdate_hz = 0\n").light_update_hz, 0);
  EXPECT_EQ(parse_service_config("[light]\nupdate_hz = 12.5\n").light_update_hz, 12.5);
  for (const char* bad : {"-1", "0.5", "1001", "\"often\""})
    EXPECT_THROW(parse_service_config(std::string("[light]\nupdate_hz = ") + bad + "\n"),
                 ParseError)
        << bad;
}

// A typo must not fall back silently to a default: the error names the key and its line.
TEST(ServiceConfig, UnknownKeyIsAnErrorWithItsLine) {
  try {
    parse_service_config("[http]\nport = 1\nprot = 2\n", "svc.toml");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("prot"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("svc.toml:3"), std::string::npos) << e.what();
  }
}

TEST(ServiceConfig, BadValuesAreErrors) {
  EXPECT_THROW(parse_service_config("[http]\nport = 70000\n"), ParseError);
  // Past int: an error, not its low 32 bits (4294975616 = 2^32 + 8320 used to bind 8320).
  try {
    parse_service_config("[http]\nport = 4294975616\n", "svc.toml");
    ADD_FAILURE() << "no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("port: 4294975616 is out of range"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_service_config("[http]\nport = \"80\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nshape = \"teapot\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nposition = [1, 2]\n"), ParseError);
  EXPECT_THROW(parse_service_config("[output]\nformat = \"gif\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[source\nrig = 1\n"), ParseError);  // TOML syntax
  EXPECT_THROW(load_service_config("/nonexistent/probeless.toml"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\nmains_hz = -50\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\ninitial_exposure_ms = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\ngpio_line = -1\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\nenabled = 1\n"), ParseError);
  EXPECT_THROW(parse_service_config("[bracket]\nmains = 50\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nface_size = 4\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nface_size = 80\n"), ParseError);  // not x32
  EXPECT_THROW(parse_service_config("[light]\nkeyframe_distance_m = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nmax_keyframes = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nmax_keyframes = 257\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nmax_keyframes = 1.5\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nroom = \"cube\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[light]\nroom = \"box\"\nroom_min = [0, 0, 0]\n"), ParseError);
  EXPECT_THROW(
      parse_service_config("[light]\nroom = \"box\"\nroom_min = [0, 0, 0]\nroom_max = [1, 1, 0]\n"),
      ParseError);  // flat
  EXPECT_THROW(parse_service_config("[light]\nroom_min = [0, 0, 0]\nroom_max = [1, 1, 1]\n"),
               ParseError);  // a box without room = "box"
  EXPECT_EQ(parse_service_config("[light]\nroom = \"sim\"\n").light_room, "sim");
  EXPECT_EQ(parse_service_config("").light_room, "auto");
  EXPECT_THROW(parse_service_config("[[object]]\nmaterial = \"velvet\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nroughness = 1.5\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nior = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nsize_m = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nalbedo = [0.5, 2, 0.5]\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nheight = 1\n"), ParseError);
}

// The configuration the package installs runs the sim (with its room box for parallax: room
// "auto" takes the sim's) on loopback; it sets no key, so a board it names decides
// (tests/unit/boards/board_file_test.cpp "TheShippedConfigurationLetsTheBoardDecide").
TEST(ServiceConfig, TheShippedConfigurationParses) {
  const ServiceConfig c =
      load_service_config(PROBELESS_TEST_SOURCE_DIR "/../../../systemd/probeless.toml");
  EXPECT_EQ(c.source, "sim");
  EXPECT_EQ(c.light_room, "auto");
  EXPECT_EQ(c.http.address, "127.0.0.1");
  EXPECT_TRUE(c.board.empty());
}

// [light] room = "sim" takes the rig's room box, and only from a rig that knows one (the sim);
// "auto" (the default) is the rig's box when it has one and no box otherwise.
TEST(LightCapture, RoomFromConfiguration) {
  const Rig sim_rig = sim::make_sim_rig(sim::SimOptions{});
  const RigCalibration& calibration = sim_rig.calibration;
  const RigScene no_scene;  // a camera's or a recording's
  ServiceConfig c;
  EXPECT_EQ(LightCapture(c, calibration, sim_rig.scene).status()["room"], "sim");
  c.source = "replay:/data/rec1";
  EXPECT_EQ(LightCapture(c, calibration, no_scene).status()["room"], "off");
  c.source = "sim";
  c.light_room = "sim";
  EXPECT_NO_THROW(LightCapture(c, calibration, sim_rig.scene));
  c.source = "replay:/data/rec1";
  EXPECT_THROW(LightCapture(c, calibration, no_scene), std::invalid_argument);
  c.light_room = "box";
  c.light_room_max = Eigen::Vector3d(3, 3, 3);
  EXPECT_NO_THROW(LightCapture(c, calibration, no_scene));
}

// The sim's scene is drivers/sim's own geometry, and the demo objects stand 0.15 m either side
// of its anchor, as default_objects() placed them when it read the anchor itself.
TEST(RigScene, TheSimsAnchorAndRoomPlaceTheDemoScene) {
  const Rig rig = sim::make_sim_rig(sim::SimOptions{});
  ASSERT_TRUE(rig.scene.object_anchor && rig.scene.room);
  EXPECT_EQ(*rig.scene.object_anchor, sim::object_anchor());
  EXPECT_EQ(rig.scene.room->lo, sim::room_bounds()[0]);
  EXPECT_EQ(rig.scene.room->hi, sim::room_bounds()[1]);
  // Recordings of the sim share its world: a rig without an anchor stands objects there too.
  EXPECT_EQ(default_object_anchor(), sim::object_anchor());

  ServiceConfig c;
  place_objects(c.objects, rig.scene);
  ASSERT_EQ(c.objects.size(), 2u);
  EXPECT_EQ(*c.objects[0].position, sim::object_anchor() + Eigen::Vector3d(-0.15, 0.0, 0.0));
  EXPECT_EQ(*c.objects[1].position, sim::object_anchor() + Eigen::Vector3d(0.15, 0.0, 0.0));
  // A position from the config wins; an object without one stands on the anchor.
  ObjectConfig placed, unplaced;
  placed.position = Eigen::Vector3d(1, 2, 3);
  EXPECT_EQ(object_position(placed, rig.scene), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(object_position(unplaced, rig.scene), sim::object_anchor());
  RigScene elsewhere;
  elsewhere.object_anchor = Eigen::Vector3d(1, 0, 0.5);
  EXPECT_EQ(object_position(c.objects[0], elsewhere), *c.objects[0].position);  // already placed
  EXPECT_TRUE(object_position(default_objects()[0], elsewhere)
                  .isApprox(Eigen::Vector3d(0.85, 0, 0.5), 1e-15));
}

// [rtsp] is additive: off by default, every key parsed, bad values named with their line.
TEST(ServiceConfig, RtspSection) {
  const ServiceConfig d = parse_service_config("");
  EXPECT_FALSE(d.rtsp.enabled);
  EXPECT_EQ(d.rtsp.port, 8554);
  EXPECT_EQ(d.rtsp.path, "/probeless");
  EXPECT_EQ(d.rtsp.encoder, "auto");
  const ServiceConfig c = parse_service_config(R"([rtsp]
enabled = true
address = "0.0.0.0"
port = 9554
path = "/cam/main"
bitrate_kbps = 4000
keyframe_interval = 15
framerate = 25
encoder = "x264enc"
)");
  EXPECT_TRUE(c.rtsp.enabled);
  EXPECT_EQ(c.rtsp.address, "0.0.0.0");
  EXPECT_EQ(c.rtsp.port, 9554);
  EXPECT_EQ(c.rtsp.path, "/cam/main");
  EXPECT_EQ(c.rtsp.bitrate_kbps, 4000);
  EXPECT_EQ(c.rtsp.keyframe_interval, 15);
  EXPECT_EQ(c.rtsp.framerate, 25);
  EXPECT_THROW(parse_service_config("[rtsp]\nframerate = 0\n"), ParseError);
  EXPECT_EQ(c.rtsp.encoder, "x264enc");
  EXPECT_THROW(parse_service_config("[rtsp]\nport = 70000\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\nbitrate_kbps = 10\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\nkeyframe_interval = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\nencoder = \"nvenc\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\nmount = \"/x\"\n"), ParseError);
  try {
    parse_service_config("[rtsp]\nenabled = true\npath = \"probeless\"\n", "svc.toml");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("path"), std::string::npos) << e.what();
  }
}

// [webrtc]: off by default, loopback ICE by default, every key parsed, bad values named.
TEST(ServiceConfig, WebRtcSection) {
  const ServiceConfig d = parse_service_config("");
  EXPECT_FALSE(d.webrtc.enabled);
  EXPECT_EQ(d.webrtc.ice_addresses, std::vector<std::string>{"127.0.0.1"});
  EXPECT_EQ(d.webrtc.max_sessions, 8);
  const ServiceConfig c = parse_service_config(R"([webrtc]
enabled = true
ice_addresses = ["192.168.1.20", "::1"]
max_sessions = 2
gather_timeout_ms = 500
disconnected_timeout_s = 30
)");
  EXPECT_TRUE(c.webrtc.enabled);
  EXPECT_EQ(c.webrtc.ice_addresses, (std::vector<std::string>{"192.168.1.20", "::1"}));
  EXPECT_EQ(c.webrtc.max_sessions, 2);
  EXPECT_EQ(c.webrtc.gather_timeout_ms, 500);
  EXPECT_EQ(c.webrtc.disconnected_timeout_s, 30);
  EXPECT_TRUE(parse_service_config("[webrtc]\nice_addresses = []\n").webrtc.ice_addresses.empty());
  EXPECT_THROW(parse_service_config("[webrtc]\nice_addresses = [\"box.local\"]\n"), ParseError);
  EXPECT_THROW(parse_service_config("[webrtc]\nice_addresses = \"127.0.0.1\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[webrtc]\nmax_sessions = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[webrtc]\ngather_timeout_ms = 5\n"), ParseError);
  EXPECT_THROW(parse_service_config("[webrtc]\ndisconnected_timeout_s = 2\n"), ParseError);
  EXPECT_THROW(parse_service_config("[webrtc]\nstun = \"stun://x\"\n"), ParseError);
}

}  // namespace
}  // namespace probeless

namespace probeless {
namespace {

// [http]'s access keys (app/outputs/http_access.hpp): an auth scheme without its secret is
// refused at start rather than served open.
TEST(ServiceConfig, HttpAccessKeys) {
  const ServiceConfig c = parse_service_config(
      "[http]\nallowed_hosts = [\"probeless.local\"]\nauth = \"basic\"\nuser = \"u\"\n"
      "password = \"p\"\ncors_origin = \"https://dash.local\"\nmax_streams_per_peer = 2\n");
  EXPECT_EQ(c.http.access.allowed_hosts, std::vector<std::string>{"probeless.local"});
  EXPECT_EQ(c.http.access.auth, HttpAuth::Basic);
  EXPECT_EQ(c.http.access.user, "u");
  EXPECT_EQ(c.http.access.cors_origin, "https://dash.local");
  EXPECT_EQ(c.http.access.max_streams_per_peer, 2);
  EXPECT_EQ(parse_service_config("").http.access.auth, HttpAuth::None);
  EXPECT_THROW(parse_service_config("[http]\nauth = \"digest\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[http]\nauth = \"basic\"\nuser = \"u\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[http]\nauth = \"bearer\"\ntoken = \"short\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[http]\nallowed_hosts = \"x\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[http]\nallowed_hosts = [1]\n"), ParseError);
  EXPECT_THROW(parse_service_config("[http]\nmax_streams_per_peer = -1\n"), ParseError);
}

}  // namespace
}  // namespace probeless

namespace probeless {
namespace {

TEST(ServiceConfig, RtspAccessKeys) {
  const ServiceConfig c =
      parse_service_config("[rtsp]\nuser = \"viewer\"\npassword = \"s3cret\"\nmax_sessions = 4\n");
  EXPECT_EQ(c.rtsp.user, "viewer");
  EXPECT_EQ(c.rtsp.password, "s3cret");
  EXPECT_EQ(c.rtsp.max_sessions, 4);
  EXPECT_EQ(parse_service_config("").rtsp.max_sessions, 16);
  EXPECT_THROW(parse_service_config("[rtsp]\nuser = \"viewer\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\npassword = \"x\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[rtsp]\nmax_sessions = -1\n"), ParseError);
}

// [output] caps (issue #20): sizes in MB, ages in minutes, what happens when full.
TEST(ServiceConfig, OutputCaps) {
  const ServiceConfig none = parse_service_config("");
  EXPECT_EQ(none.files.max_bytes, 0u);
  EXPECT_EQ(none.files.max_age.count(), 0);
  EXPECT_FALSE(none.files.stop_when_full);
  const ServiceConfig c = parse_service_config(
      "[output]\ndir = \"/var/lib/probeless/frames\"\nmax_mb = 2048\nkeep_minutes = 90\n"
      "when_full = \"stop\"\n");
  EXPECT_EQ(c.files.max_bytes, 2048u * 1'000'000u);
  EXPECT_EQ(c.files.max_age.count(), 90);
  EXPECT_TRUE(c.files.stop_when_full);
  for (const char* bad : {"max_mb = -1", "keep_minutes = -5", "keep_minutes = 600000",
                          "when_full = \"delete\"", "max_mb = 1.5"}) {
    try {
      parse_service_config(std::string("[output]\n") + bad + "\n", "svc.toml");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), 2) << e.what();
    }
  }
}

}  // namespace
}  // namespace probeless

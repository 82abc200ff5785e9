#include "app/pipeline/service_config.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

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
  EXPECT_EQ(c.http_address, "127.0.0.1");
  EXPECT_EQ(c.http_port, 8080);
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
  EXPECT_EQ(c.http_port, 9000);
  EXPECT_EQ(c.output_format, "png");
  EXPECT_TRUE(c.output_matte);
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
  EXPECT_THROW(parse_service_config("[[object]]\nmaterial = \"velvet\"\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nroughness = 1.5\n"), ParseError);
  EXPECT_THROW(parse_service_config("[[object]]\nior = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nsize_m = 0\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nalbedo = [0.5, 2, 0.5]\n"), ParseError);
  EXPECT_THROW(parse_service_config("[ground]\nheight = 1\n"), ParseError);
}

}  // namespace
}  // namespace probeless

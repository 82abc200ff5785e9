// The board files of board/ and how a config names one (docs/boards.md): every shipped
// board.toml goes through the real loader, and a config laid over a board wins key by key.
#include "app/pipeline/board_file.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "app/pipeline/service_config.hpp"
#include "core/calibration.hpp"
#include "core/error.hpp"
#include "drivers/openni2/openni2_rgbd_source.hpp"
#include "drivers/rig_factory.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "drivers/sim/sim_sources.hpp"
#include "drivers/v4l2/v4l2_fisheye_source.hpp"
#include "drivers/v4l2/v4l2_options.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

namespace fs = std::filesystem;

const fs::path kBoards = fs::path(PROBELESS_TEST_SOURCE_DIR) / "../../../board";

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// The message of the ParseError that `load` throws; fails the test when it throws none.
template <typename F>
std::string parse_error(F&& load) {
  try {
    load();
  } catch (const ParseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ParseError";
  return {};
}

// A fisheye spec without its "&calibration=FILE" (the rig's, not the camera's).
std::string without_calibration(std::string spec) {
  const auto at = spec.find("&calibration=");
  if (at == std::string::npos) return spec;
  const auto end = spec.find('&', at + 1);
  return spec.erase(at, end == std::string::npos ? std::string::npos : end - at);
}

class BoardDir : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("PROBELESS_BOARD_DIR", kBoards.c_str(), 1); }
  void TearDown() override { ::unsetenv("PROBELESS_BOARD_DIR"); }
};

TEST(BoardFiles, EveryShippedBoardLoadsWithTheServiceLoader) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(kBoards)) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename();
    SCOPED_TRACE(name);
    names.insert(name);
    EXPECT_TRUE(fs::is_regular_file(entry.path() / "README.md")) << "bring-up README missing";
    const ServiceConfig c = load_service_config("", entry.path().string());
    EXPECT_EQ(c.about_name, name) << "[about] name must be the directory's name";
    EXPECT_EQ(fs::canonical(c.board), fs::canonical(entry.path() / "board.toml"));
    EXPECT_FALSE(c.cl_platform.empty()) << "a board says which OpenCL platform it uses";
    EXPECT_NE(c.source, "sim") << "a board names its sensors";
    // The fisheye part of the rig spec must be one the V4L2 driver accepts (the rig factory
    // takes calibration= out before the driver sees the rest).
    const auto v4l2 = c.source.find("+v4l2:");
    ASSERT_NE(v4l2, std::string::npos);
    EXPECT_NO_THROW(v4l2::parse_v4l2_options(without_calibration(c.source.substr(v4l2 + 6))));
  }
  EXPECT_EQ(names, (std::set<std::string>{"rk3588", "rpi5", "x86-pocl"}));
}

TEST_F(BoardDir, AConfigNamesABoardAndOverridesItKeyByKey) {
  const fs::path dir = testing::scratch_dir();
  write(dir / "probeless.toml",
        "board = \"rpi5\"\n[http]\nport = 9000\n[bracket]\nmains_hz = 60\n");
  const ServiceConfig c = load_service_config((dir / "probeless.toml").string());
  EXPECT_EQ(c.about_name, "rpi5");
  EXPECT_EQ(c.http.port, 9000);              // the config's
  EXPECT_EQ(c.http.address, "0.0.0.0");      // the board's, same table
  EXPECT_EQ(c.bracket.mains_hz, 60);         // the config's
  EXPECT_EQ(c.trigger_chip, "pinctrl-rp1");  // the board's, same table
  EXPECT_EQ(c.trigger_line, 17);
  EXPECT_EQ(c.cl_platform, "Portable Computing Language");
  EXPECT_EQ(fs::canonical(c.board), fs::canonical(kBoards / "rpi5/board.toml"));
}

// Issue #18: "add board = NAME" to the shipped /etc/probeless/probeless.toml (or run with
// --board NAME) and the board's sensors open, never the sim: the shipped file sets none of
// the keys a board sets, so nothing it says overrides the board.
TEST_F(BoardDir, TheShippedConfigurationLetsTheBoardDecide) {
  const fs::path shipped = fs::path(PROBELESS_TEST_SOURCE_DIR) / "../../../systemd/probeless.toml";
  std::ifstream in(shipped);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty());
  const fs::path dir = testing::scratch_dir();
  for (const std::string name : {"rpi5", "rk3588", "x86-pocl"}) {
    SCOPED_TRACE(name);
    // The person's edit: one line on top of the shipped file.
    write(dir / name / "probeless.toml", "board = \"" + name + "\"\n" + text);
    const ServiceConfig named = load_service_config((dir / name / "probeless.toml").string());
    const ServiceConfig flag = load_service_config(shipped.string(), name);
    const ServiceConfig board = load_service_config("", name);
    for (const ServiceConfig* c : {&named, &flag}) {
      EXPECT_EQ(c->about_name, name);
      EXPECT_EQ(c->source, board.source);                           // the board's sensors ...
      EXPECT_TRUE(c->source.starts_with("openni2:")) << c->source;  // ... the real RGB-D,
      EXPECT_NE(c->source.find("+v4l2:"), std::string::npos) << c->source;  // the fisheye,
      EXPECT_NE(c->source.find("calibration=/etc/probeless/calibration.toml"), std::string::npos)
          << c->source;  // the unit's calibration, not the sim's
      EXPECT_EQ(c->source.find("sim"), std::string::npos) << c->source;
      EXPECT_EQ(c->http.address, board.http.address);
      EXPECT_EQ(c->bracket.mains_hz, board.bracket.mains_hz);
      EXPECT_EQ(c->light_room, "auto");  // a real rig has no room box: parallax off
      EXPECT_EQ(c->cl_platform, board.cl_platform);
    }
  }
}

// What the rig factory makes of a board's spec with the shipped config: OpenNI2's RGB-D source
// and the V4L2 fisheye (in "no device" here, where neither is plugged in), the unit's
// calibration, and no synthetic room. (tests/vm/check_vivid.sh streams the same kind of spec
// from OpenNI2's Dummy device and vivid.)
TEST_F(BoardDir, ABoardsSpecOpensItsOwnDevicesNeverTheSim) {
  const fs::path dir = testing::scratch_dir();
  RigCalibration unit = sim::make_sim_rig(sim::SimOptions{}).calibration;
  unit.T_rig_fisheye.translation.x() = 0.123;  // not the sim's: the file's must arrive
  write(dir / "calibration.toml", to_toml(unit));
  for (const std::string name : {"rpi5", "rk3588", "x86-pocl"}) {
    SCOPED_TRACE(name);
    std::string spec = load_service_config("", name).source;
    const std::string shipped_calibration = "calibration=/etc/probeless/calibration.toml";
    ASSERT_NE(spec.find(shipped_calibration), std::string::npos);
    spec.replace(spec.find(shipped_calibration), shipped_calibration.size(),
                 "calibration=" + (dir / "calibration.toml").string());
    Rig rig = open_rig(spec);
    EXPECT_NE(dynamic_cast<openni2::Openni2RgbdSource*>(rig.rgbd.get()), nullptr);
    EXPECT_NE(dynamic_cast<v4l2::V4l2FisheyeSource*>(rig.fisheye.get()), nullptr);
    EXPECT_EQ(dynamic_cast<sim::SimRgbdSource*>(rig.rgbd.get()), nullptr);
    EXPECT_FALSE(rig.scene.room.has_value());
    EXPECT_DOUBLE_EQ(rig.calibration.T_rig_fisheye.translation.x(), 0.123);
  }
  // Without the unit's calibration file: an error naming it, at start-up.
  try {
    open_rig(load_service_config("", "rpi5").source);
    ADD_FAILURE() << "opened without a calibration file";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/etc/probeless/calibration.toml"), std::string::npos)
        << e.what();
  }
}

TEST_F(BoardDir, TheCommandLineBoardWinsOverTheFilesAndWorksAlone) {
  const fs::path dir = testing::scratch_dir();
  write(dir / "probeless.toml", "board = \"rpi5\"\n[http]\nport = 9000\n");
  const ServiceConfig c = load_service_config((dir / "probeless.toml").string(), "x86-pocl");
  EXPECT_EQ(c.about_name, "x86-pocl");
  EXPECT_EQ(c.trigger_chip, "");
  EXPECT_EQ(c.http.port, 9000);
  EXPECT_EQ(load_service_config("", "rk3588").cl_platform, "ARM Platform");
  // Neither a file nor a board: the built-in defaults.
  EXPECT_EQ(load_service_config("").source, "sim");
}

TEST(BoardFiles, PathsAreRelativeToTheFileThatNamesThem) {
  const fs::path dir = testing::scratch_dir();
  write(dir / "boards/mine/board.toml",
        "[source]\nrig = \"sim\"\n[[object]]\nmodel = \"duck.gltf\"\n");
  write(dir / "conf/probeless.toml", "board = \"../boards/mine\"\n[http]\nport = 1234\n");
  const ServiceConfig c = load_service_config((dir / "conf/probeless.toml").string());
  EXPECT_EQ(c.http.port, 1234);
  ASSERT_EQ(c.objects.size(), 1u);
  EXPECT_EQ(fs::path(c.objects[0].model), dir / "boards/mine/duck.gltf");
  // An [[object]] list in the config replaces the board's whole list.
  write(dir / "conf/objects.toml",
        "board = \"../boards/mine/board.toml\"\n"
        "[[object]]\nshape = \"box\"\n[[object]]\nshape = \"sphere\"\n");
  const ServiceConfig o = load_service_config((dir / "conf/objects.toml").string());
  ASSERT_EQ(o.objects.size(), 2u);
  EXPECT_EQ(o.objects[0].shape, "box");
}

TEST_F(BoardDir, ErrorsNameTheFileAndLineAtFault) {
  const fs::path dir = testing::scratch_dir();
  const std::string config = (dir / "probeless.toml").string();

  write(config, "[http]\nport = 1\nboard = \"rpi6\"\n");  // `board` inside [http]
  EXPECT_NE(parse_error([&] { load_service_config(config); }).find("unknown key 'board'"),
            std::string::npos);

  write(config, "# the board\nboard = \"rpi6\"\n");
  std::string what = parse_error([&] { load_service_config(config); });
  EXPECT_NE(what.find(config + ":2:"), std::string::npos) << what;
  EXPECT_NE(what.find("board 'rpi6'"), std::string::npos) << what;
  EXPECT_NE(what.find("rk3588, rpi5, x86-pocl"), std::string::npos) << what;  // what exists

  write(config, "board = 5\n");
  EXPECT_NE(parse_error([&] { load_service_config(config); }).find("expected a string"),
            std::string::npos);

  write(config, "board = \"./nowhere\"\n");
  EXPECT_NE(parse_error([&] { load_service_config(config); }).find("no file"), std::string::npos);

  // A typo in the board file names the board file; one in the config names the config.
  const fs::path board = dir / "b/board.toml";
  write(board, "[opencl]\nplatform = \"x\"\n\n[http]\nprot = 80\n");
  write(config, "board = \"./b\"\n[http]\nport = 80\n");
  what = parse_error([&] { load_service_config(config); });
  EXPECT_NE(what.find(board.string() + ":5: unknown key 'prot'"), std::string::npos) << what;
  write(board, "[opencl]\nplatform = \"x\"\n");
  write(config, "board = \"./b\"\n\n[opencl]\ndevise = \"y\"\n");
  what = parse_error([&] { load_service_config(config); });
  EXPECT_NE(what.find(config + ":4: unknown key 'devise'"), std::string::npos) << what;

  // Boards do not chain.
  write(board, "board = \"rpi5\"\n");
  what = parse_error([&] { load_service_config(config); });
  EXPECT_NE(what.find(board.string() + ":1: a board file cannot name another board"),
            std::string::npos)
      << what;

  // A name looked up where there are no boards says where it looked.
  ::setenv("PROBELESS_BOARD_DIR", (dir / "empty").c_str(), 1);
  what = parse_error([] { load_service_config("", "rpi5"); });
  EXPECT_NE(what.find("boards in " + (dir / "empty").string() + ": none"), std::string::npos)
      << what;
}

// "file:line" a node was parsed from.
std::string origin(toml::node_view<toml::node> view) {
  const toml::node* node = view.node();
  if (!node || !node->source().path) return "?";
  return *node->source().path + ":" + std::to_string(node->source().begin.line);
}

TEST(BoardFiles, MergeKeepsTheSourcePositionsOfBothFiles) {
  using std::string_view;
  toml::table base = toml::parse(string_view("[a]\nx = 1\ny = 2\n"), string_view("base.toml"));
  toml::table over =
      toml::parse(string_view("\n[a]\ny = 3\n[b]\nz = 4\n"), string_view("over.toml"));
  merge_toml(base, std::move(over));
  EXPECT_EQ(base["a"]["x"].value<int>(), 1);
  EXPECT_EQ(base["a"]["y"].value<int>(), 3);
  EXPECT_EQ(base["b"]["z"].value<int>(), 4);
  EXPECT_EQ(origin(base["a"]["x"]), "base.toml:2");
  EXPECT_EQ(origin(base["a"]["y"]), "over.toml:3");
  EXPECT_EQ(origin(base["b"]["z"]), "over.toml:5");
}

}  // namespace
}  // namespace probeless

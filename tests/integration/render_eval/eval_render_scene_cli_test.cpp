// `probeless eval render --list-scenes` and `--scene` as a user runs them: the real binary,
// its output and exit codes (docs/fusion.md). The scenes themselves are measured by hand (a
// run takes ~15 s per scene): docs/fusion.md has the table.
#include <gtest/gtest.h>

#include "support/subprocess.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(EvalRenderScene, ListsTheMovingObjectScenesOneALine) {
  std::string out;
  ASSERT_EQ(testing::run_to_end(testing::probeless_binary(), {"eval", "render", "--list-scenes"},
                                &out, 60s),
            0)
      << out;
  EXPECT_EQ(out, "box_slides\nhand_approaches\nbox_removed\nbox_appears\n");
}

TEST(EvalRenderScene, AnUnknownSceneIsAnErrorNamingTheValidOnes) {
  std::string out;
  const int rc = testing::run_to_end(testing::probeless_binary(),
                                     {"eval", "render", "--scene", "box_flies"}, &out, 60s);
  EXPECT_NE(rc, 0);
  EXPECT_NE(out.find("unknown scene 'box_flies'"), std::string::npos) << out;
  EXPECT_NE(out.find("box_slides, hand_approaches, box_removed, box_appears"), std::string::npos)
      << out;
  // The default protocol's options do not mix with a scene.
  const int rc2 =
      testing::run_to_end(testing::probeless_binary(),
                          {"eval", "render", "--scene", "box_slides", "--orbit", "3"}, &out, 60s);
  EXPECT_NE(rc2, 0);
  EXPECT_NE(out.find("do not apply"), std::string::npos) << out;
  // The fusion column's map is the reference or the device's, and only a scene has one.
  const int rc3 = testing::run_to_end(
      testing::probeless_binary(),
      {"eval", "render", "--scene", "box_slides", "--fusion-map", "gpu"}, &out, 60s);
  EXPECT_NE(rc3, 0);
  EXPECT_NE(out.find("unknown --fusion-map 'gpu' (reference, device)"), std::string::npos) << out;
  const int rc4 = testing::run_to_end(testing::probeless_binary(),
                                      {"eval", "render", "--fusion-map", "device"}, &out, 60s);
  EXPECT_NE(rc4, 0);
  EXPECT_NE(out.find("--fusion-map applies to a --scene only"), std::string::npos) << out;
}

}  // namespace
}  // namespace probeless

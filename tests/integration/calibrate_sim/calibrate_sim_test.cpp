// Issue #18's sim bar for calibration: the sim's scripted calibration views
// (`trajectory=calibration`, drivers/sim/sim_calibration_views.hpp) recorded with
// `probeless record`, calibrated with `probeless calibrate --recording`, against the sim's
// true calibration; then `eval light` with the recovered calibration against the true one.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/calibration.hpp"
#include "core/camera/kannala_brandt.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "drivers/sim/sim_calibration_views.hpp"
#include "drivers/sim/sim_rig.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

int run(const std::vector<std::string>& args, std::string* output) {
  return testing::run_to_end(testing::probeless_binary(), args, output, 600s);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

double relative(double value, double truth) {
  return std::abs(value - truth) / std::abs(truth);
}

// The colour camera's pose in the rig frame is where the two calibrations meet: the fisheye in
// the colour camera's frame.
Pose rgb_to_fisheye(const RigCalibration& c) {
  return c.T_rig_rgb.inverse() * c.T_rig_fisheye;
}

double at_probe_rmse(const fs::path& json) {
  return read_json(json)["at_probe"]["all"]["relative_rmse"].get<double>();
}

// 1 frame per second: one scripted pose per frame; 1024 px: 6-7 px per marker cell on the
// fisheye at 0.45 m.
constexpr const char* kSource =
    "sim:trajectory=calibration,fps=1,fisheye_fps=1,realtime=0,fisheye_size=1024";

TEST(CalibrateSim, RecordedCalibrationViewsRecoverTheSimsCalibration) {
  const fs::path dir = testing::scratch_dir();
  const std::string frames = std::to_string(sim::calibration_view_count());
  std::string log;
  ASSERT_EQ(run({"record", "--source", kSource, "--frames", frames, (dir / "rec").string()}, &log),
            0)
      << log;
  ASSERT_EQ(run({"calibrate", "--recording", (dir / "rec").string(), "--board", sim::board_spec(),
                 "--out", (dir / "rig.toml").string(), "--json", (dir / "rig.json").string()},
                &log),
            0)
      << log;
  const RigCalibration truth = replay::load_rig_calibration(dir / "rec" / "calibration.toml");
  const RigCalibration rig = replay::load_rig_calibration(dir / "rig.toml");
  const auto j = read_json(dir / "rig.json");
  // The board is found in every view the script gives each camera: the colour camera's 41
  // (14 of them alone, over its lower half, its sides and its centre, tilted 35-45 deg about
  // both axes), the fisheye's 36, 24 pairs. Views whose pose cv::fisheye failed to start (corners
  // 80-95 deg off its axis) join the joint refinement once posed (kannala_brandt_refine.hpp).
  EXPECT_EQ(j["rgb"]["views_used"], 41) << log;
  EXPECT_EQ(j["fisheye"]["views"].size(), 36u) << log;
  EXPECT_EQ(j["fisheye"]["views_used"], 36) << log;
  EXPECT_GE(j["views_used"], 22) << log;
  // OpenCV's standard deviations are reported; the principal point's was 1.5 / 1.2 px from
  // the 27 colour views of the earlier script, 1.35 / 1.09 px now (seed 1; seed 2 1.33 / 1.06).
  ASSERT_TRUE(j["rgb"].contains("std_dev")) << j["rgb"].dump();
  EXPECT_LT(j["rgb"]["std_dev"]["cx"].get<double>(), 1.45);
  EXPECT_LT(j["rgb"]["std_dev"]["cy"].get<double>(), 1.15);
  EXPECT_GT(j["rgb"]["std_dev"]["cx"].get<double>(), 0);
  EXPECT_FALSE(j["fisheye"].contains("std_dev"));

  // Intrinsics within 0.5 % (issue #18). Measured (seed 1): colour fx +0.09 %, cx +0.20 %;
  // fisheye fx -0.21 % (docs/calibration.md "Checked on the sim").
  const auto& k = rig.rgb.intrinsics();
  const auto& kt = truth.rgb.intrinsics();
  EXPECT_LT(relative(k.fx, kt.fx), 0.005) << k.fx;
  EXPECT_LT(relative(k.fy, kt.fy), 0.005) << k.fy;
  EXPECT_LT(relative(k.cx, kt.cx), 0.005) << k.cx;
  EXPECT_LT(relative(k.cy, kt.cy), 0.005) << k.cy;
  const auto* kb = dynamic_cast<const KannalaBrandtCamera*>(rig.fisheye.get());
  const auto* kbt = dynamic_cast<const KannalaBrandtCamera*>(truth.fisheye.get());
  ASSERT_NE(kb, nullptr);
  ASSERT_NE(kbt, nullptr);
  EXPECT_LT(relative(kb->params().fx, kbt->params().fx), 0.005) << kb->params().fx;
  EXPECT_LT(relative(kb->params().fy, kbt->params().fy), 0.005) << kb->params().fy;
  EXPECT_LT(relative(kb->params().cx, kbt->params().cx), 0.005) << kb->params().cx;
  EXPECT_LT(relative(kb->params().cy, kbt->params().cy), 0.005) << kb->params().cy;
  // The domain ends at the lens's image circle (95 deg), not at the frame's dark corners.
  EXPECT_NEAR(kb->params().max_theta, kbt->params().max_theta, 0.02);

  // Extrinsics: issue #18 asks 2 mm and 0.2 deg. Measured 0.65 mm and 0.052 deg (seed 2: 0.56
  // mm, 0.042 deg); 1.08 mm and 0.080 deg before the script had the 14 colour-only views that
  // pin the colour camera's principal point better (docs/calibration.md "Checked on the sim").
  const Pose want = rgb_to_fisheye(truth), got = rgb_to_fisheye(rig);
  const double t_err = (got.translation - want.translation).norm();
  const double r_err = got.rotation.angularDistance(want.rotation) * 180 / std::numbers::pi;
  EXPECT_LT(t_err, 0.002) << t_err * 1000 << " mm\n" << log;
  EXPECT_LT(r_err, 0.2) << r_err << " deg\n" << log;
  std::cout << log << "T_rgb_fisheye error: " << t_err * 1000 << " mm, " << r_err << " deg\n";

  // eval light with the sim's own calibration given as a file is the default run exactly; with
  // the recovered one, what its calibration errors cost.
  const std::vector<std::string> eval{"eval", "light", "--source",
                                      "sim",  "--sim", "fisheye_size=1024"};
  const auto eval_with = [&](const std::vector<std::string>& extra, const fs::path& json) {
    std::vector<std::string> args = eval;
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"--json", json.string()});
    std::string out;
    EXPECT_EQ(run(args, &out), 0) << out;
    return at_probe_rmse(json);
  };
  const double plain = eval_with({}, dir / "plain.json");
  const double given_truth =
      eval_with({"--calibration", (dir / "rec" / "calibration.toml").string()}, dir / "truth.json");
  const double recovered =
      eval_with({"--calibration", (dir / "rig.toml").string()}, dir / "recovered.json");
  EXPECT_DOUBLE_EQ(given_truth, plain);
  // Issue #18 asks within 10 %. Measured 0.0757 against 0.0725 (+4.4 %; seed 2's calibration
  // +5.0 %); +14 % with the earlier 39-view script. The texel error follows the fisheye's
  // orientation across the window's and the lamps' edges (docs/calibration.md).
  EXPECT_LT(recovered, plain * 1.10) << recovered << " vs " << plain;
  std::cout << "eval light at the object, relative RMSE: true calibration " << plain
            << ", recovered " << recovered << "\n";
}

TEST(CalibrateSim, BadInputsAreClearErrors) {
  const fs::path dir = testing::scratch_dir();
  std::string out;
  EXPECT_NE(
      run({"record", "--source", "sim:trajectory=calibrate", "--frames", "1", (dir / "r").string()},
          &out),
      0);
  EXPECT_NE(out.find("static, orbit, handheld, tabletop or calibration"), std::string::npos) << out;
  // A calibration whose fisheye is not the sim's size.
  EXPECT_NE(run({"eval", "light", "--source", "sim", "--seconds", "0.1", "--calibration",
                 (dir / "missing.toml").string()},
                &out),
            0);
  EXPECT_NE(out.find("missing.toml"), std::string::npos) << out;
  RigCalibration small = sim::make_sim_rig(sim::parse_sim_options("fisheye_size=256")).calibration;
  std::ofstream(dir / "small.toml") << to_toml(small);
  EXPECT_NE(run({"eval", "light", "--source", "sim", "--seconds", "0.1", "--calibration",
                 (dir / "small.toml").string()},
                &out),
            0);
  EXPECT_NE(out.find("256x256 but the sim's is 512x512"), std::string::npos) << out;
}

TEST(CalibrateSim, ScriptedPosesHoldForASecondAndRepeat) {
  const int n = sim::calibration_view_count();
  EXPECT_GE(n, 20);
  const auto same = [](const Pose& a, const Pose& b) {
    return (a.translation - b.translation).norm() < 1e-9 &&
           a.rotation.angularDistance(b.rotation) < 1e-9;
  };
  EXPECT_TRUE(same(sim::calibration_rig_pose(0.0), sim::calibration_rig_pose(0.99)));
  EXPECT_FALSE(same(sim::calibration_rig_pose(0.0), sim::calibration_rig_pose(1.0)));
  EXPECT_TRUE(same(sim::calibration_rig_pose(2.5), sim::calibration_rig_pose(2.5 + n)));
  // Every pose looks at the board from above the table.
  for (int i = 0; i < n; ++i)
    EXPECT_GT(sim::calibration_rig_pose(i).translation.z(), sim::table_top_height_m() + 0.25) << i;
}

}  // namespace
}  // namespace probeless

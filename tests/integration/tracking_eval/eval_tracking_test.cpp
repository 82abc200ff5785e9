// `probeless eval tracking` and `probeless bench tracking` as a user runs them: the real
// binary, its JSON, its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "drivers/io/png.hpp"
#include "support/subprocess.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// Runs probeless with `args`; returns the exit status (-1 on timeout). `output` gets stdout
// and stderr.
int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  return testing::run_to_end(testing::probeless_binary(), args, output, 600s);
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

const char* kMetricKeys[] = {"ate_rmse_m", "rpe_t_m", "rpe_r_deg", "reg_px_p50",
                             "reg_px_p95", "p50_ms",  "p99_ms",    "lost_frames"};

// A TUM-layout folder of `frames` flat grey frames, with or without groundtruth.txt.
fs::path make_tum_folder(const fs::path& dir, int frames, bool ground_truth) {
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  std::ofstream rgb(dir / "rgb.txt"), depth(dir / "depth.txt");
  for (int i = 0; i < frames; ++i) {
    const std::string stamp = std::to_string(100 + i * 0.033);
    write_png(dir / ("rgb/" + stamp + ".png"), ImageRGB8(640, 480, 128));
    write_png(dir / ("depth/" + stamp + ".png"), DepthImage(640, 480, 10000));
    rgb << stamp << " rgb/" << stamp << ".png\n";
    depth << stamp << " depth/" << stamp << ".png\n";
  }
  if (ground_truth) {
    std::ofstream gt(dir / "groundtruth.txt");
    gt << "99.0 0 0 0 0 0 0 1\n102.0 0 0 0 0 0 0 1\n";
  }
  return dir;
}

// fr1/rpy's first 150 frames: OpenCV's odometry tracks them within a few centimetres (a
// wrong pose chaining, intrinsics or truth convention gives decimetres or worse).
TEST(EvalTracking, TumFr1RpyReportsEveryMethodWithPlausibleNumbers) {
  PROBELESS_REQUIRE_DATA("rgbd/tum_fr1_rpy/groundtruth.txt");
  const auto out = testing::scratch_dir() / "fr1_rpy.json";
  std::string output;
  ASSERT_EQ(run({"eval", "tracking", "--dataset",
                 "tum:" + (testing::shared_data_dir() / "rgbd/tum_fr1_rpy").string(), "--json",
                 out.string()},
                &output),
            0)
      << output;
  EXPECT_NE(output.find("TUM fr1 published"), std::string::npos) << output;
  const auto j = read_json(out);
  EXPECT_EQ(j.at("sequence"), "tum_fr1_rpy");
  EXPECT_EQ(j.at("frames"), 150);
  const auto& methods = j.at("methods");
  ASSERT_EQ(methods.size(), 5u) << j.dump(2);
  for (const char* name : {"dense", "dense_cpu", "opencv_rgbd", "opencv_icp", "opencv_rgbdicp"}) {
    ASSERT_TRUE(methods.contains(name)) << name;
    const auto& m = methods.at(name);
    EXPECT_EQ(m.size(), 8u) << name;
    for (const char* key : kMetricKeys) EXPECT_TRUE(m.contains(key)) << name << " " << key;
  }
  for (const char* name : {"opencv_rgbd", "opencv_icp", "opencv_rgbdicp"}) {
    const auto& m = methods.at(name);
    EXPECT_LT(m.at("ate_rmse_m").get<double>(), 0.2) << name;
    EXPECT_GT(m.at("ate_rmse_m").get<double>(), 0.0) << name;
    EXPECT_LT(m.at("rpe_t_m").get<double>(), 0.2) << name;
    EXPECT_LT(m.at("rpe_r_deg").get<double>(), 15.0) << name;
    EXPECT_LT(m.at("reg_px_p50").get<double>(), 100.0) << name;
    EXPECT_LE(m.at("reg_px_p50").get<double>(), m.at("reg_px_p95").get<double>()) << name;
    EXPECT_GT(m.at("p50_ms").get<double>(), 0.0) << name;
    EXPECT_LE(m.at("p50_ms").get<double>(), m.at("p99_ms").get<double>()) << name;
    EXPECT_LE(m.at("lost_frames").get<int>(), 5) << name;
  }
}

TEST(EvalTracking, SimOrbitAgainstItsTruth) {
  const auto out = testing::scratch_dir() / "sim.json";
  const auto trajectories = testing::scratch_dir() / "trajectories";
  const auto per_frame = testing::scratch_dir() / "per_frame.csv";
  std::string output;
  ASSERT_EQ(run({"eval", "tracking", "--dataset", "sim:seed=2", "--frames", "40", "--methods",
                 "opencv_rgbd,dense_cpu", "--json", out.string(), "--trajectories",
                 trajectories.string(), "--per-frame", per_frame.string()},
                &output),
            0)
      << output;
  const auto j = read_json(out);
  EXPECT_EQ(j.at("sequence"), "sim:seed=2");
  EXPECT_EQ(j.at("frames"), 40);
  const auto& m = j.at("methods").at("opencv_rgbd");
  for (const char* key : kMetricKeys) EXPECT_TRUE(m.contains(key)) << key;
  // 1.3 s of the orbit (0.23 m, 8 degrees): well under the distance travelled.
  EXPECT_LT(m.at("ate_rmse_m").get<double>(), 0.1);
  // TUM trajectory files: a comment line and one line of 8 numbers per frame.
  for (const char* name : {"opencv_rgbd.txt", "dense_cpu.txt", "groundtruth.txt"}) {
    std::ifstream in(trajectories / name);
    int lines = 0;
    for (std::string line; std::getline(in, line);) {
      if (line.starts_with("#")) continue;
      std::istringstream fields(line);
      double v;
      int n = 0;
      while (fields >> v) ++n;
      EXPECT_EQ(n, 8) << name << ": " << line;
      ++lines;
    }
    EXPECT_EQ(lines, 40) << name;
  }
  // --per-frame: a row per frame and method; the dense tracker names its reference keyframe
  // (frame 0 first), OpenCV's frame-to-frame methods none; the sim sees the anchor throughout.
  std::ifstream csv(per_frame);
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line,
            "frame,timestamp_s,method,lost,keyframe,reg_px,rotation_error_deg,"
            "translation_error_m");
  std::map<std::string, int> rows;
  std::map<std::string, std::vector<double>> reg;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
    ASSERT_EQ(f.size(), 8u) << line;
    const int frame = std::stoi(f[0]);
    EXPECT_EQ(frame, rows[f[2]]++) << line;
    EXPECT_EQ(f[3], "0") << line;
    if (f[2] == "dense_cpu") {
      EXPECT_TRUE(frame == 0 ? f[4] == "0" : std::stoi(f[4]) >= 0) << line;
    } else {
      EXPECT_EQ(f[4], "-1") << line;
    }
    ASSERT_FALSE(f[5].empty()) << line;
    if (frame == 0) {
      EXPECT_EQ(std::stod(f[5]), 0.0) << line;
    }
    reg[f[2]].push_back(std::stod(f[5]));
    if (f[2] == "dense_cpu") {  // the sim's orbit: the dense tracker is within a pixel or two
      EXPECT_LT(std::stod(f[6]), 0.5) << line;
      EXPECT_LT(std::stod(f[7]), 0.05) << line;
    }
  }
  for (auto& [name, values] : reg) {  // the rows are the numbers the report's quantiles take
    std::sort(values.begin(), values.end());
    EXPECT_NEAR((values[19] + values[20]) / 2, j.at("methods").at(name).at("reg_px_p50"), 2e-3)
        << name;
  }
  EXPECT_EQ(rows["dense_cpu"], 40);
  EXPECT_EQ(rows["opencv_rgbd"], 40);
}

TEST(EvalTracking, BadInputsGiveClearErrors) {
  const auto dir = testing::scratch_dir();
  const auto no_truth = make_tum_folder(dir / "no_truth", 3, false);
  const auto with_truth = make_tum_folder(dir / "tum_fr1_flat", 3, true);
  {
    std::ofstream bad(dir / "bad.toml");
    bad << "[rgb]\nfx = \"five hundred\"\n";
  }
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"--dataset", "tum:" + (dir / "missing").string()}, "not a directory"},
      {{"--dataset", "tum:" + with_truth.string(), "--methods", "opencv_rgbd,orb_slam"},
       "unknown tracking method 'orb_slam'"},
      {{"--dataset", "tum:" + with_truth.string() + "?calibration=" + (dir / "bad.toml").string()},
       "bad.toml"},
      {{"--dataset", "tum:" + with_truth.string() + "?calibration=" + (dir / "none.toml").string()},
       "none.toml does not exist"},
      {{"--dataset", "tum:" + no_truth.string()}, "no groundtruth.txt"},
      {{"--dataset", "kitti:" + dir.string()}, "expected tum:DIR"},
      {{"--dataset", "sim", "--frames", "2", "--methods", "opencv_rgbd", "--per-frame",
        dir.string()},
       "cannot write"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args{"eval", "tracking"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"--json", (dir / "out.json").string()});
    std::string output;
    EXPECT_NE(run(args, &output), 0) << c.args[1];
    EXPECT_NE(output.find(c.message), std::string::npos) << c.args[1] << ":\n" << output;
  }
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

TEST(BenchTracking, ReportsDenseAndTheFastestOpenCvMethod) {
  const auto out = testing::scratch_dir() / "bench.json";
  std::string output;
  ASSERT_EQ(run({"bench", "tracking", "--dataset", "sim", "--frames", "12", "--methods",
                 "dense,opencv_rgbd,opencv_icp", "--json", out.string()},
                &output),
            0)
      << output;
  const auto j = read_json(out);
  for (const char* key : {"p50_ms", "p99_ms", "cpu_ms"}) {
    EXPECT_GT(j.at(key).get<double>(), 0.0) << key;
    EXPECT_GT(j.at("fastest_opencv").at(key).get<double>(), 0.0) << key;
  }
  EXPECT_EQ(j.at("width"), 640);
  EXPECT_EQ(j.at("height"), 480);
  const std::string fastest = j.at("fastest_opencv").at("method");
  EXPECT_TRUE(fastest == "opencv_rgbd" || fastest == "opencv_icp") << fastest;
  EXPECT_LE(j.at("fastest_opencv").at("p50_ms").get<double>(),
            j.at("methods").at("opencv_rgbd").at("p50_ms").get<double>());
  EXPECT_NE(run({"bench", "tracking", "--frames", "1"}, &output), 0);
  EXPECT_NE(output.find("--frames must be in 2..1000"), std::string::npos) << output;
}

}  // namespace
}  // namespace probeless

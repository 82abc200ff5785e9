// probeless eval light --source sim: the light estimator on the sim's slow orbit against the
// sim's ground-truth radiance (docs/light-capture.md "eval light").
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "lab/cli/lab_commands.hpp"
#include "lab/eval/light_eval.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string source = "sim";
  std::string json;
  std::string rule = "kalman";
  std::string parallax = "on";
  light::LightEvalOptions eval;
};

nlohmann::json face_json(const light::FaceError& f) {
  nlohmann::json j{{"observed", f.observed}};
  j["relative_rmse"] = f.relative_rmse ? nlohmann::json(*f.relative_rmse) : nlohmann::json();
  return j;
}

nlohmann::json comparison_json(const light::TruthComparison& c) {
  static const char* kFaces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  nlohmann::json faces;
  for (int f = 0; f < 6; ++f) faces[kFaces[f]] = face_json(c.faces[f]);
  return {{"truth", c.truth},
          {"faces", faces},
          {"all", face_json(c.all)},
          {"sh25_relative_error", c.sh25_relative_error},
          {"sh9_relative_error", c.sh9_relative_error}};
}

void print(const std::string& label, const light::TruthComparison& c) {
  static const char* kFaces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  std::cout << fmt::format("  vs {}:\n   ", label);
  for (int f = 0; f < 6; ++f) {
    const auto& e = c.faces[f];
    std::cout << fmt::format(" {} {}", kFaces[f],
                             e.relative_rmse ? fmt::format("{:.3f}", *e.relative_rmse) : "-");
  }
  std::cout << fmt::format(
      "\n    all observed texels ({}): relative RMSE {}; SH error 25: {:.3f}, 9: {:.3f}\n",
      c.all.observed, c.all.relative_rmse ? fmt::format("{:.4f}", *c.all.relative_rmse) : "-",
      c.sh25_relative_error, c.sh9_relative_error);
}

void run(Options& o) {
  if (o.source != "sim") throw CommandError("eval light: only --source sim has ground truth");
  if (o.rule == "kalman")
    o.eval.estimator.update.rule = envmap::UpdateRule::Kalman;
  else if (o.rule == "best_score")
    o.eval.estimator.update.rule = envmap::UpdateRule::BestScore;
  else
    throw CommandError("eval light: --rule is kalman or best_score");
  if (o.parallax != "on" && o.parallax != "off")
    throw CommandError("eval light: --parallax is on or off");
  o.eval.room_box = o.parallax == "on";
  light::LightEvalReport r;
  try {
    r = light::evaluate_light_sim(o.eval);
  } catch (const std::invalid_argument& e) {
    throw CommandError(e.what());
  } catch (const ParseError& e) {  // a --calibration file that does not load
    throw CommandError(std::string("eval light: --calibration: ") + e.what());
  }
  std::cout << fmt::format(
      "eval light: {} fisheye frames ({} s of sim time), rule {}, {} keyframe(s); keyframe "
      "{} is {:.2f} m from the object; radiance scale {:.4f} (exact, from the sim's sensor)\n",
      r.frames, o.eval.seconds, r.rule, r.keyframes, r.keyframe_id, r.keyframe_distance_m, r.scale);
  std::cout << fmt::format("  parallax: {}\n", r.room_box ? "room box (the sim's room), keyframe "
                                                            "reprojected to where it is compared"
                                                          : "off (distant light)");
  print("the truth at the object (FrameTruth::light)", r.at_probe);
  if (r.room_box)
    print("the truth at the object, keyframe not reprojected", r.at_probe_unreprojected);
  print("the truth at the keyframe's position", r.at_keyframe);
  print(fmt::format("the truth at the fisheye's last position ({:.2f} m from the keyframe's)",
                    r.keyframe_to_last_capture_m),
        r.at_last_capture);
  std::cout << fmt::format(
      "  per frame: p50 {:.2f} ms, p99 {:.2f} ms; exposures settled after {} cycles\n",
      r.total.p50_ms, r.total.p99_ms, r.settle_cycles);
  if (!o.json.empty()) {
    const nlohmann::json j{
        {"frames", r.frames},
        {"calibration",
         o.eval.calibration_file.empty() ? std::string("sim") : o.eval.calibration_file},
        {"seconds", o.eval.seconds},
        {"rule", r.rule},
        {"keyframes", r.keyframes},
        {"keyframe_id", r.keyframe_id},
        {"keyframe_distance_m", r.keyframe_distance_m},
        {"radiance_scale", r.scale},
        {"settle_cycles", r.settle_cycles},
        {"parallax", r.room_box ? "room_box" : "off"},
        {"at_probe", comparison_json(r.at_probe)},
        {"at_probe_unreprojected", comparison_json(r.at_probe_unreprojected)},
        {"at_keyframe", comparison_json(r.at_keyframe)},
        {"at_last_capture", comparison_json(r.at_last_capture)},
        {"keyframe_to_last_capture_m", r.keyframe_to_last_capture_m},
        {"p50_ms", r.total.p50_ms},
        {"p99_ms", r.total.p99_ms}};
    write_json_report(o.json, j);
  }
}

}  // namespace

void add_eval_light_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "light", "Light capture on the sim's slow orbit against its ground-truth radiance");
  cmd->add_option("--source", o->source, "Source with ground truth (sim)")->capture_default_str();
  cmd->add_option("--seconds", o->eval.seconds, "Sim time to run")->capture_default_str();
  cmd->add_option("--sim", o->eval.sim_spec, "Extra sim options (seed=2,fisheye_size=1024,...)");
  cmd->add_option("--rule", o->rule, "Texel update: kalman or best_score")->capture_default_str();
  cmd->add_option("--parallax", o->parallax,
                  "on: the sim's room box in the update, keyframes reprojected to the "
                  "object and the last capture; off: distant light")
      ->capture_default_str();
  cmd->add_option("--face-size", o->eval.estimator.keyframes.face_size, "Keyframe face size")
      ->capture_default_str();
  cmd->add_option("--calibration", o->eval.calibration_file,
                  "Run light capture with this rig calibration TOML (e.g. from probeless "
                  "calibrate) instead of the sim's true one");
  cmd->add_option("--json", o->json, "Write the report as JSON");
  cmd->add_option("--dump", o->eval.dump_dir,
                  "Write DIR/compare.png: keyframe | truth there, reprojected to the object | "
                  "truth there, reprojected to the last capture | truth there");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli

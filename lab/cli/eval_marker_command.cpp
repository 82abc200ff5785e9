// probeless eval marker: a ChArUco board in one real photo, its pose and the corner
// reprojection RMS (issue #17 item 5; lab/eval/marker_eval.hpp, docs/tracking.md "Boards").
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "lab/cli/lab_commands.hpp"
#include "lab/eval/marker_eval.hpp"

namespace probeless::cli {
namespace {

struct Options {
  std::string image, camera, board = "charuco:5x7:40:20:6x6_250", json;
};

void run(const Options& o) {
  eval::BoardPose pose;
  try {
    const BoardSpec board = parse_board_spec(o.board);
    pose = eval::find_board_pose(o.image, eval::read_opencv_camera(o.camera), board);
  } catch (const std::exception& e) {
    throw CommandError(e.what());
  }
  if (pose.found) {
    std::cout << fmt::format(
        "{}: board found: {} markers, {} of {} corners; t = [{:.4f}, {:.4f}, {:.4f}] m, "
        "rotation {:.2f} deg; corner reprojection RMS {:.3f} px (max {:.3f})\n",
        o.image, pose.markers, pose.corners, pose.board_corners, pose.t_m[0], pose.t_m[1],
        pose.t_m[2], pose.rotation_deg, pose.rms_px, pose.max_px);
  } else {
    std::cout << fmt::format("{}: board NOT found ({} markers, {} corners)\n", o.image,
                             pose.markers, pose.corners);
  }
  if (!o.json.empty()) {
    nlohmann::json j{{"image", o.image},        {"board", o.board},
                     {"found", pose.found},     {"markers", pose.markers},
                     {"corners", pose.corners}, {"board_corners", pose.board_corners}};
    if (pose.found) {
      j["t_m"] = pose.t_m;
      j["rvec"] = pose.rvec;
      j["rotation_deg"] = pose.rotation_deg;
      j["rms_px"] = pose.rms_px;
      j["max_px"] = pose.max_px;
    }
    write_json_report(o.json, j);
  }
  if (!pose.found) throw CommandError("no board pose in " + o.image);
}

}  // namespace

void add_eval_marker_command(CLI::App& eval) {
  auto o = std::make_shared<Options>();
  auto* cmd = eval.add_subcommand(
      "marker", "A ChArUco board in a photo: its pose and the corner reprojection RMS (px)");
  cmd->add_option("--image", o->image, "Photo (any format OpenCV reads)")->required();
  cmd->add_option("--camera", o->camera,
                  "OpenCV calibration file with camera_matrix and distortion_coefficients")
      ->required();
  cmd->add_option("--board", o->board,
                  "charuco:COLSxROWS:SQUARE_MM:MARKER_MM:DICT (COLS x ROWS squares)")
      ->capture_default_str();
  cmd->add_option("--json", o->json, "Write the result as JSON");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli

// probeless calibrate: camera intrinsics and the rig's extrinsics from board views, or an
// OCamCalib file imported (issue #18 item 1; lab/calib/, docs/calibration.md).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/camera/pinhole.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "lab/calib/board_detector.hpp"
#include "lab/calib/camera_toml.hpp"
#include "lab/calib/image_circle.hpp"
#include "lab/calib/intrinsics.hpp"
#include "lab/calib/rig_extrinsics.hpp"
#include "lab/calib/view_image.hpp"
#include "lab/calib/view_sources.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {
namespace fs = std::filesystem;
using namespace probeless::calib;

struct Options {
  std::string images, board, model = "pinhole", camera_out, views_out, json;
  std::string import_ocam;
  std::string recording, rgb_images, fisheye_images, out, intrinsics;
  int max_views = 80;  // the sim's calibration script is 59 views (docs/calibration.md)
};

void progress(const std::string& line) {
  fmt::print(stderr, "calibrate: {}\n", line);
}

std::string found_text(const std::optional<BoardView>& v, const BoardDetector& d) {
  return v ? fmt::format("{} of {} corners", v->pixels.size(), d.corner_count())
           : std::string("board not found");
}

nlohmann::json intrinsics_json(const Intrinsics& in) {
  nlohmann::json views = nlohmann::json::array();
  for (const ViewFit& v : in.views)
    views.push_back({{"file", v.name},
                     {"rms_px", v.rms_px},
                     {"corners", v.corners},
                     {"tilt_deg", v.tilt_deg},
                     {"used", v.in_fit}});
  nlohmann::json out = {{"model", lens_model_name(in.model)},
                        {"width", in.width},
                        {"height", in.height},
                        {"fx", in.fx},
                        {"fy", in.fy},
                        {"cx", in.cx},
                        {"cy", in.cy},
                        {"distortion", in.distortion},
                        {"rms_px", in.rms_px},
                        {"tilt_spread_deg", in.tilt_spread_deg},
                        {"views_used", std::count_if(in.views.begin(), in.views.end(),
                                                     [](const ViewFit& v) { return v.in_fit; })},
                        {"views", views}};
  // OpenCV's standard deviations (pinhole only): fx fy cx cy, then the distortion's terms.
  if (!in.std_dev.empty())
    out["std_dev"] = {
        {"fx", in.std_dev[0]},
        {"fy", in.std_dev[1]},
        {"cx", in.std_dev[2]},
        {"cy", in.std_dev[3]},
        {"distortion", std::vector<double>(in.std_dev.begin() + 4, in.std_dev.end())}};
  return out;
}

nlohmann::json pose_json(const Pose& p) {
  const auto& q = p.rotation;
  return {{"translation", {p.translation.x(), p.translation.y(), p.translation.z()}},
          {"rotation_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

void print_intrinsics(const std::string& what, const Intrinsics& in) {
  std::cout << fmt::format(
      "{} ({}, {}x{}): fx {:.3f} fy {:.3f} cx {:.3f} cy {:.3f} distortion [{:.5g}]; RMS {:.3f} "
      "px over {} views\n",
      what, lens_model_name(in.model), in.width, in.height, in.fx, in.fy, in.cx, in.cy,
      fmt::join(in.distortion, ", "), in.rms_px, in.views.size());
  if (!in.std_dev.empty())
    std::cout << fmt::format("  standard deviations: fx {:.2f} fy {:.2f} cx {:.2f} cy {:.2f} px\n",
                             in.std_dev[0], in.std_dev[1], in.std_dev[2], in.std_dev[3]);
  if (in.tilt_spread_deg < kWeakTiltSpreadDeg)
    progress(fmt::format(
        "warning: the {} views' boards differ in orientation by at most {:.1f} deg, so the "
        "focal length is weakly determined: add views tilted 20-40 deg in other directions",
        what, in.tilt_spread_deg));
}

void require_views(std::size_t found, std::size_t images, const std::string& where) {
  if (static_cast<int>(found) < kMinViews)
    throw CommandError(fmt::format(
        "too few views: the board was found in {} of {} images of {}; at least {} are needed "
        "(show the whole board, tilted 20-40 deg in different directions)",
        found, images, where, kMinViews));
}

void write_views(const fs::path& dir, const std::string& prefix,
                 const std::vector<BoardView>& views, const std::vector<ImageGray8>& images,
                 const std::vector<ViewFit>& fits) {
  fs::create_directories(dir);
  for (std::size_t i = 0; i < views.size(); ++i)
    write_view_png(dir / (prefix + fs::path(views[i].name).stem().string() + ".png"), images[i],
                   views[i], fits[i].reprojected, fits[i].rms_px);
}

// One camera of the rig: calibrated from its views, or given (--intrinsics) and only its
// board poses found.
struct CameraSide {
  std::shared_ptr<const CameraModel> camera;
  std::vector<ViewFit> fits;  // in the order of the views
  nlohmann::json json;
};

CameraSide calibrated_side(const std::string& what, const std::vector<BoardView>& views,
                           std::size_t images, const std::string& where, LensModel model,
                           const std::vector<ImageGray8>& view_images = {}) {
  require_views(views.size(), images, what + " in " + where);
  Intrinsics in = calibrate_intrinsics(views, model);
  // A fisheye's domain ends at its image circle where the views show one.
  if (model == LensModel::KannalaBrandt)
    in.image_circle = image_circle_radius(view_images, in.fx, in.fy, in.cx, in.cy);
  print_intrinsics(what, in);
  return {in.camera(), in.views, intrinsics_json(in)};
}

CameraSide fixed_side(const std::string& what, std::shared_ptr<const CameraModel> camera,
                      const std::vector<BoardView>& views, const std::string& file) {
  CameraSide side{std::move(camera), {}, {}};
  nlohmann::json json_views = nlohmann::json::array();
  double sum = 0;
  std::size_t n = 0;
  for (const BoardView& v : views) {
    ViewFit fit = fit_board_pose(*side.camera, v);
    json_views.push_back({{"file", v.name}, {"rms_px", fit.rms_px}, {"corners", fit.corners}});
    sum += fit.rms_px * fit.rms_px * fit.corners;
    n += static_cast<std::size_t>(fit.corners);
    side.fits.push_back(std::move(fit));
  }
  const double rms = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
  std::cout << fmt::format(
      "{} ({}, {}x{}): as given by {}; board poses RMS {:.3f} px over {} views\n", what,
      side.camera->kind(), side.camera->width(), side.camera->height(), file, rms, views.size());
  side.json = {{"model", side.camera->kind()},
               {"given_by", file},
               {"rms_px", rms},
               {"views_used", views.size()},
               {"views", json_views}};
  return side;
}

void import_ocam(const Options& o) {
  if (o.camera_out.empty()) throw CommandError("--import-ocam needs --camera-out F.toml");
  const auto camera = read_ocam_file(o.import_ocam);
  std::cout << write_camera_toml(o.camera_out, camera) << "\n";
}

void calibrate_camera(const Options& o) {
  const auto model = parse_lens_model(o.model);
  if (!model) throw CommandError("--model '" + o.model + "': expected pinhole or kannala-brandt");
  const BoardDetector detector(parse_board_spec(o.board));
  const auto files = list_images(o.images);
  std::vector<BoardView> views;
  std::vector<ImageGray8> images;  // kept for --views-out only
  for (std::size_t i = 0; i < files.size(); ++i) {
    ImageGray8 gray = read_gray_image(files[i]);
    auto view = detector.detect(gray, files[i].filename().string());
    progress(fmt::format("[{}/{}] {}: {}", i + 1, files.size(), files[i].filename().string(),
                         found_text(view, detector)));
    if (!view) continue;
    views.push_back(std::move(*view));
    if (!o.views_out.empty()) images.push_back(std::move(gray));
  }
  require_views(views.size(), files.size(), o.images);
  const Intrinsics in = calibrate_intrinsics(views, *model);
  print_intrinsics("camera", in);
  if (!o.views_out.empty()) write_views(o.views_out, "", views, images, in.views);
  if (!o.camera_out.empty()) std::cout << write_camera_toml(o.camera_out, in.camera()) << "\n";
  if (!o.json.empty()) write_json_report(o.json, intrinsics_json(in));
}

void calibrate_rig(const Options& o) {
  if (o.out.empty()) throw CommandError("--out FILE is needed: the rig calibration to write");
  if (o.recording.empty() && (o.rgb_images.empty() || o.fisheye_images.empty()))
    throw CommandError("--rgb-images and --fisheye-images go together");
  const BoardDetector detector(parse_board_spec(o.board));
  std::vector<StereoImages> pairs;
  double depth_baseline_m = RigCalibration{}.depth_baseline_m;
  if (!o.recording.empty()) {
    pairs = recording_pairs(o.recording, o.max_views, &depth_baseline_m);
  } else {
    int unmatched = 0;
    for (const ImagePair& p : matching_images(o.rgb_images, o.fisheye_images, &unmatched))
      pairs.push_back({p.name, read_gray_image(p.rgb), read_gray_image(p.fisheye)});
    if (unmatched > 0)
      progress(
          fmt::format("{} images have no partner of the same name in the other folder", unmatched));
  }

  std::vector<BoardView> rgb_views, fisheye_views;
  std::vector<ImageGray8> rgb_images, fisheye_images;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    auto rgb = detector.detect(pairs[i].rgb, pairs[i].name);
    auto fisheye = detector.detect(pairs[i].fisheye, pairs[i].name);
    progress(fmt::format("[{}/{}] {}: colour {}, fisheye {}", i + 1, pairs.size(), pairs[i].name,
                         found_text(rgb, detector), found_text(fisheye, detector)));
    if (rgb) {
      rgb_views.push_back(std::move(*rgb));
      rgb_images.push_back(std::move(pairs[i].rgb));
    }
    if (fisheye) {
      fisheye_views.push_back(std::move(*fisheye));
      fisheye_images.push_back(std::move(pairs[i].fisheye));
    }
  }
  const std::string source = o.recording.empty() ? o.rgb_images : o.recording;
  CameraSide rgb, fisheye;
  if (!o.intrinsics.empty()) {
    const RigCalibration given = replay::load_rig_calibration(o.intrinsics);
    if (!given.fisheye)
      throw CommandError(o.intrinsics + " has no [fisheye]: --intrinsics needs both cameras");
    rgb = fixed_side("colour camera", std::make_shared<PinholeCamera>(given.rgb), rgb_views,
                     o.intrinsics);
    fisheye = fixed_side("fisheye", given.fisheye, fisheye_views, o.intrinsics);
  } else {
    rgb = calibrated_side("colour camera", rgb_views, pairs.size(), source, LensModel::Pinhole);
    fisheye = calibrated_side("fisheye", fisheye_views, pairs.size(), source,
                              LensModel::KannalaBrandt, fisheye_images);
  }

  std::map<std::string, std::size_t> fisheye_index;
  for (std::size_t i = 0; i < fisheye_views.size(); ++i) fisheye_index[fisheye_views[i].name] = i;
  std::vector<StereoView> stereo;
  for (std::size_t i = 0; i < rgb_views.size(); ++i) {
    const auto it = fisheye_index.find(rgb_views[i].name);
    if (it == fisheye_index.end()) continue;
    const BoardView& f = fisheye_views[it->second];
    stereo.push_back({rgb_views[i].name, rgb_views[i].points, rgb_views[i].pixels, f.points,
                      f.pixels, rgb.fits[i].T_camera_board,
                      fisheye.fits[it->second].T_camera_board});
  }
  const auto rgb_camera = rgb.camera;
  const auto fisheye_camera = fisheye.camera;
  const RigExtrinsics ext = solve_rig_extrinsics(*rgb_camera, *fisheye_camera, stereo);
  const Eigen::Vector3d& t = ext.T_rgb_fisheye.translation;
  const int used = static_cast<int>(
      std::count_if(ext.views.begin(), ext.views.end(), [](const auto& v) { return v.used; }));
  std::cout << fmt::format(
      "T_rig_fisheye: translation [{:.4f}, {:.4f}, {:.4f}] m, rotation {:.3f} deg; RMS {:.3f} px "
      "(colour {:.3f}, fisheye {:.3f}; initial {:.3f}) over {} of {} views seen by both\n",
      t.x(), t.y(), t.z(),
      Eigen::AngleAxisd(ext.T_rgb_fisheye.rotation).angle() * 180.0 / 3.141592653589793, ext.rms_px,
      ext.rgb_rms_px, ext.fisheye_rms_px, ext.initial_rms_px, used, stereo.size());

  RigCalibration rig;
  if (const auto* pinhole = dynamic_cast<const PinholeCamera*>(rgb_camera.get()))
    rig.rgb = *pinhole;
  rig.fisheye = fisheye_camera;
  rig.T_rig_rgb = Pose::identity();  // the rig frame is the colour camera's
  rig.T_rig_fisheye = ext.T_rgb_fisheye;
  rig.depth_baseline_m = depth_baseline_m;
  write_rig_toml(o.out, rig);
  std::cout << "wrote " << o.out << "\n";
  if (!o.views_out.empty()) {
    write_views(o.views_out, "colour_", rgb_views, rgb_images, rgb.fits);
    write_views(o.views_out, "fisheye_", fisheye_views, fisheye_images, fisheye.fits);
  }
  if (!o.json.empty()) {
    nlohmann::json views = nlohmann::json::array();
    for (const StereoViewFit& v : ext.views)
      views.push_back({{"file", v.name},
                       {"rgb_rms_px", v.rgb_rms_px},
                       {"fisheye_rms_px", v.fisheye_rms_px},
                       {"used", v.used}});
    write_json_report(o.json, {{"rgb", rgb.json},
                               {"fisheye", fisheye.json},
                               {"T_rig_rgb", pose_json(rig.T_rig_rgb)},
                               {"T_rig_fisheye", pose_json(rig.T_rig_fisheye)},
                               {"initial_T_rig_fisheye", pose_json(ext.initial_T_rgb_fisheye)},
                               {"rms_px", ext.rms_px},
                               {"rgb_rms_px", ext.rgb_rms_px},
                               {"fisheye_rms_px", ext.fisheye_rms_px},
                               {"initial_rms_px", ext.initial_rms_px},
                               {"iterations", ext.iterations},
                               {"views_used", used},
                               {"views", views}});
  }
}

void run(const Options& o) {
  const int modes = int{!o.images.empty()} + int{!o.import_ocam.empty()} +
                    int{!o.recording.empty()} +
                    int{!o.rgb_images.empty() || !o.fisheye_images.empty()};
  if (modes != 1)
    throw CommandError(
        "calibrate takes one of --images DIR (one camera), --import-ocam FILE, --recording DIR "
        "or --rgb-images DIR with --fisheye-images DIR (the rig)");
  if (!o.intrinsics.empty() && o.recording.empty() && o.rgb_images.empty())
    throw CommandError("--intrinsics goes with --recording or --rgb-images (the rig)");
  if (o.import_ocam.empty() && o.board.empty())
    throw CommandError(
        "--board SPEC is needed (e.g. charuco:5x7:40:20:6x6_250 or "
        "chessboard:9x6:25)");
  try {
    if (!o.import_ocam.empty()) {
      import_ocam(o);
    } else if (!o.images.empty()) {
      calibrate_camera(o);
    } else {
      calibrate_rig(o);
    }
  } catch (const CommandError&) {
    throw;
  } catch (const std::exception& e) {
    throw CommandError(e.what());
  }
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "calibrate",
      "Camera intrinsics and rig extrinsics from board views, or an OCamCalib file imported "
      "(the lab: probeless-lab; docs/calibration.md)");
  cmd->add_option("--images", o->images, "One camera: a folder of board images");
  cmd->add_option("--board", o->board,
                  "charuco:COLSxROWS:SQUARE_MM:MARKER_MM:DICT (squares) or "
                  "chessboard:COLSxROWS:SQUARE_MM (inner corners)");
  cmd->add_option("--model", o->model, "With --images: pinhole or kannala-brandt")
      ->capture_default_str();
  cmd->add_option("--camera-out", o->camera_out,
                  "With --images or --import-ocam: write the camera's TOML (added to this file "
                  "if it is already a rig calibration)");
  cmd->add_option("--import-ocam", o->import_ocam,
                  "An OCamCalib calib_results.txt to write as the fisheye's TOML");
  cmd->add_option("--recording", o->recording,
                  "The rig: a recording made with `probeless record` (both streams)");
  cmd->add_option("--rgb-images", o->rgb_images,
                  "The rig: a folder of colour images (pairs matched by file name)");
  cmd->add_option("--fisheye-images", o->fisheye_images, "The rig: a folder of fisheye images");
  cmd->add_option("--max-views", o->max_views,
                  "With --recording: at most this many frame pairs, spread evenly")
      ->capture_default_str()
      ->check(CLI::Range(3, 1000));
  cmd->add_option("--out", o->out, "The rig calibration TOML to write");
  cmd->add_option("--intrinsics", o->intrinsics,
                  "The rig: take both cameras' models from this rig calibration TOML (e.g. an "
                  "imported OCamCalib fisheye) and solve the extrinsics only");
  cmd->add_option("--views-out", o->views_out,
                  "Write a PNG per view: detected corners (green) and reprojections (red)");
  cmd->add_option("--json", o->json, "Write the result as JSON");
  cmd->callback([o] { run(*o); });
}

}  // namespace probeless::cli

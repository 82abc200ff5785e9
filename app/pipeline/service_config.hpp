#pragma once
// The service's configuration: what `probeless run --config FILE` reads (TOML, documented in
// docs/configuration.md). Every field has a default so that `probeless run` with no file runs
// the synthetic rig with a built-in object.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/outputs/file_output.hpp"
#include "app/outputs/http_server.hpp"
#include "app/outputs/kms_display.hpp"
#include "app/outputs/rtsp_server.hpp"
#include "app/outputs/webrtc_output.hpp"
#include "app/world/world_config.hpp"
#include "core/beyond_range.hpp"
#include "drivers/bracket/bracket_sequencer.hpp"

namespace probeless {

struct ObjectConfig {
  std::string shape = "pawn";  // built-in: "pawn", "sphere", "box"; ignored when model is set
  std::string model;           // path to a .gltf/.glb/.obj file (relative to the config file)
  std::optional<Eigen::Vector3d> position;  // world metres; default: the rig's object anchor
  // Without a position: where the object stands from the rig's object anchor (not a config
  // key; the demo scene's objects stand beside each other across it). place_objects()
  // resolves it once the rig is known (app/pipeline/scene_objects.hpp).
  Eigen::Vector3d anchor_offset = Eigen::Vector3d::Zero();
  double yaw_deg = 0;  // rotation about world z
  double scale = 1.0;
  Eigen::Vector3f colour{0.75f, 0.18f, 0.12f};  // linear base colour
  // How it is shaded (docs/rendering.md "Materials"): lambert (fixed placeholder light),
  // mirror, metal (rough, colour = F0), glass (refraction), diffuse (SH irradiance, no
  // shadows), prt (diffuse with self-shadowing and a shadow on the ground plane).
  std::string material = "lambert";
  double roughness = 0.3;  // metal: perceptual roughness in [0, 1]
  double ior = 1.5;        // glass: index of refraction (glass 1.5, water 1.33)
};

// [ground]: the real plane the objects stand on, which receives their shadows (differential
// rendering, docs/rendering.md). From config until it is found in the depth image.
struct GroundConfig {
  bool enabled = true;
  std::optional<double> height_m;  // world z of the plane; default: the objects' lowest base
  double size_m = 0.8;             // side of the square receiver grid around the objects
  Eigen::Vector3f albedo{0.45f, 0.35f, 0.25f};  // linear diffuse albedo of the real surface
};

// The demo scene of issue #6: a mirror sphere and a self-shadowed diffuse pawn side by side
// on the synthetic rig's table.
std::vector<ObjectConfig> default_objects();

struct ServiceConfig {
  // The board file under this config (docs/boards.md): as resolved by load_service_config
  // (the reference as written when only parsed); and [about] name (a board file's own name).
  std::string board;
  std::string about_name;

  std::string source = "sim";  // drivers/rig_factory.hpp spec: sim[:opts], replay:DIR, tum:DIR
  std::vector<ObjectConfig> objects = default_objects();
  GroundConfig ground;

  // The shipped CVF (local colour models) for every source, since every rig gives depth: the
  // lowest mean MSE of the evaluator's methods on Middlebury and alphamatting.com, 5.5-6.6
  // CPU-ms a 640x480 frame on PoCL (docs/occlusion.md "CVF as shipped", "Speed");
  // kernels/occlusion/method_registry.hpp lists the others.
  std::string occlusion_method = "cvf";
  // [occlusion] stabilise: the previous matte re-projected with the tracked pose and the
  // depth steadies the current one where colour and depth agree (kernels/occlusion/temporal,
  // docs/occlusion.md "Temporal stabilisation": on the sim's moving rig cvf's temporal noise
  // -55 %, MSE -13 %).
  bool occlusion_stabilise = true;
  // [occlusion] near_occluders: cvf counts the core of a wide depth hole as an occluder nearer
  // than the sensor's range (a hand at 20 cm; docs/occlusion.md "Occluders the sensor cannot
  // see": on the sim's near hand, MSE 1.9x the same hand with depth instead of 91x). Off for a
  // scene where the wide holes are far surfaces the sensor cannot measure (black, specular)
  // that neither the colour gate nor beyond_range_m catches, with virtual objects in front.
  bool occlusion_near_occluders = true;
  // [occlusion] beyond_range_m: holes whose nearest measured depth is at least this far are
  // surfaces beyond the sensor's range and get that depth before the matte
  // (core/beyond_range.hpp; docs/occlusion.md "Beyond the sensor's range": objects in front of
  // the sim's far wall, MSE x1e3 64.0 -> 4.4). 0.5 m inside a Kinect-class sensor's 4 m; set
  // it 0.5 m inside your sensor's maximum range, 0 to turn it off.
  double occlusion_beyond_range_m = BeyondRangeRule{}.far_mm / 1000.0;
  TrackingConfig tracking;
  WorldConfig world;

  // The outputs (app/outputs/output.hpp), each section its component's own config.
  HttpServerConfig http;  // [http]: the MJPEG stream, the viewer and /status
  // [rtsp]: H.264 over RTSP beside the MJPEG (docs/outputs.md "RTSP"), off by default.
  RtspServerConfig rtsp;
  // [webrtc]: H.264 over WebRTC, negotiated by WHEP on the HTTP server (docs/outputs.md
  // "WebRTC (WHEP)"), off by default; its encoder takes [rtsp]'s encoder settings.
  WebRtcConfig webrtc;
  FileOutputConfig files;  // [output]: the image sequence; no dir, no files
  // [display]: the tethered screen, EGL on GBM + KMS (docs/display.md), off by default.
  KmsDisplayConfig display;

  std::string cl_platform;  // substring match; empty: PROBELESS_CL_PLATFORM or the default
  std::string cl_device;

  // [bracket]: the fisheye's L-M-H-M exposure cycle (docs/bracketing.md). Off: the fisheye
  // keeps whatever exposure it has (a recording replays the exposures it was taken at).
  bool bracket_enabled = true;
  BracketConfig bracket;
  std::string trigger_chip;  // GPIO chip of the exposure trigger; empty: free-running camera
  int trigger_line = 0;
  // The strobe input (drivers/trigger/gpio_strobe.hpp): its edges stamp the fisheye frames.
  std::string strobe_chip;  // empty: frames keep the driver's timestamps
  int strobe_line = 0;
  std::string strobe_edge = "rising";  // "rising", "falling" or "both"

  // [light]: the HDR environment-map keyframes kept from the fisheye (docs/light-capture.md).
  bool light_enabled = true;
  // Texels per cube face edge (issue #5 asks >= 128). 192: a chrome sphere's error is mostly
  // the lamps' edges, whose share shrinks with the texel (`eval render`, seed 1: 0.122 at 128,
  // 0.095 at 192, 0.085 at 256, under issue #6's 0.10 from 192 on); 256 cost the pipeline
  // below 60 fps here, 192 keeps it at ~75 (docs/performance.md, 2026-11-26).
  int light_face_size = 192;
  double light_keyframe_distance_m = 0.5;
  // Keyframes kept (the farthest from the rig is dropped past it; docs/light-capture.md "How
  // many keyframes"). Each costs ~15 MB resident at 192 px faces (two device cubemaps of
  // 3.5 MB, the reprojection map and its reprojected texels, 8 MB; issue #20's soak), and
  // docs/security.md "Memory" budgets light capture at 256 MB on a 2 GB board: 16 x 15 = 240.
  int light_max_keyframes = 16;
  // Parallax with a room proxy (docs/light-capture.md "Parallax"): "off" (distant light, the
  // thesis's keyframes), "sim" (the synthetic rig's room; sim sources only), "box" (an
  // axis-aligned box from light_room_min to light_room_max, world metres). With a room the
  // SH is of the keyframe seen from the first object.
  // Texels the fisheye never saw (below its horizon: the table) from the colour camera
  // (kernels/light/colour_fill.hpp). On: `eval render`'s chrome sphere 0.256 -> 0.249, its lower
  // half 0.53 -> 0.25 (docs/light-capture.md "Below the horizon").
  bool light_colour_fill = true;
  // At most this many fisheye frames a second update the keyframe, in whole bracket cycles
  // (app/pipeline/light_pacing.hpp); 0: every frame. 25 against the sim's 50: `bench pipeline`
  // and `eval render` in docs/light-capture.md "Update rate".
  double light_update_hz = 25;
  std::string light_room = "auto";  // off | auto (sim's box under the sim) | sim | box
  Eigen::Vector3d light_room_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d light_room_max = Eigen::Vector3d::Zero();

  std::int64_t max_frames = 0;  // 0 = run until stopped
  // A source that has delivered nothing for this long is "no signal": outputs show the last
  // good frame with a NO SIGNAL banner. 250 ms is 7 frames at 30 Hz: long enough to ride out
  // a scheduling hiccup, short enough that a viewer sees the fault at once.
  int no_signal_after_ms = 250;
};

// Parses TOML text; throws ParseError naming the source and line on bad input, unknown keys
// included (a typo must not silently fall back to a default).
ServiceConfig parse_service_config(std::string_view toml_text,
                                   std::string_view source_name = "config.toml");
// Reads the file at `path` (empty: none) laid over the board file that `board` (else the
// file's own `board = "..."`) names, key by key (docs/boards.md); with neither, the defaults.
// A board named on the command line is looked up from the working directory, one named in a
// file from that file's directory. Throws ParseError as above, naming whichever file is wrong.
ServiceConfig load_service_config(const std::string& path, const std::string& board = {});

}  // namespace probeless

#pragma once
// The synthetic rig (docs/sim.md): a procedural room rendered on the CPU, deterministically
// from a seed, as an RGB-D source and an upward fisheye source with ground truth. It is the
// service's default source and the one every pipeline test runs on.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "drivers/source.hpp"

namespace probeless::sim {

// Tabletop: standing at the table, looking down onto it (38 degrees), swinging around the
// anchor; the view in which the board (`board=1`) anchors the world. Calibration: scripted
// poses around the board, one per second, for `probeless calibrate` (sim_calibration_views.hpp;
// the board is then always on and the arm stays away).
enum class TrajectoryKind { Static, Orbit, Handheld, Tabletop, Calibration };

// The moving-object scenes (issue #21 item 6; sim_moving_scene.hpp, docs/fusion.md): a real
// object moves next to where the virtual chrome sphere stands, at known times. None: the
// default world (the arm, as before).
enum class MovingScene { None, BoxSlides, HandApproaches, BoxRemoved, BoxAppears };

struct SimOptions {
  std::uint64_t seed = 1;
  TrajectoryKind trajectory = TrajectoryKind::Orbit;
  double rgbd_fps = 30, fisheye_fps = 30;  // nominal rates; timestamps advance by 1/fps
  // true: read() paces frames to wall-clock (never blocking longer than its timeout) and
  // skips frames a slow reader missed, as a camera would; false: as fast as the renderer goes
  // (bench, record, tests), every frame in order.
  bool realtime = true;
  // The fisheye's own pacing; unset: as `realtime`. `realtime=0,fisheye_realtime=1` is how
  // `bench pipeline` loads the machine as the appliance would: RGB-D as fast as it goes, the
  // fisheye at its real rate (a free-running 512 px fisheye rendered ~200 frames/s beside the
  // pipeline and took most of a core from it).
  std::optional<bool> fisheye_realtime;
  int fisheye_size = 512;      // square image, 64..1024
  int fisheye_bit_depth = 12;  // 8 or 12
  double fisheye_fov_deg = 190;
  // Non-empty: the fisheye is this OCamCalib calibration (calib_results.txt) instead of the
  // ideal equidistant lens, rendered through it at its own frame size (fisheye_size and
  // fisheye_fov are then unused): a rig calibrated with OCamCalib, for light capture's
  // model-independent path (docs/light-capture.md).
  std::string fisheye_ocam;
  // With fisheye_ocam: false renders and calibrates the rig with the OCamCalib model itself;
  // true with a Kannala-Brandt model least-squares fitted to it (the same lens through the
  // other model, so `eval light` compares the two models on one field of view).
  bool fisheye_ocam_as_kannala_brandt = false;
  std::int64_t max_frames = -1;  // then EndOfStream (RGB-D frames count); -1: endless
  // Fault injection for service tests: frames [stall_begin, stall_end) of the RGB-D stream are
  // not delivered: read() returns NoFrameYet and state() says NoSignal during that span (as
  // long in wall-clock time as those frames would have taken, in both modes); then it resumes.
  std::int64_t stall_begin = -1, stall_end = -1;
  // > 0: the stall repeats every this many frames (frames [begin + k every, end + k every)):
  // the soak's replug of the source every minute (lab bench soak).
  std::int64_t stall_every = 0;
  bool ground_truth = true;  // attach FrameTruth
  int render_threads = 2;    // per source; rendering is split across rows
  // A ChArUco board (board_spec()) lying on the table at board_world_pose(): ground truth for
  // world anchoring with a marker. Off by default: every other measurement on the sim (light,
  // render, occlusion) was taken on the table without it.
  bool board = false;
  // The scripted world's time at the first frame (orbit angle, lamp switches, the arm):
  // `eval render` starts shortly before a lamp switch instead of rendering 6 s to reach one.
  double start_s = 0;
  // Frames 0..prerender-1 of each stream rendered before the clock starts and then served from
  // memory: a camera's frames cost the appliance no CPU, the sim's ray casting ~half of it,
  // so `bench pipeline --prerender` measures the pipeline alone (docs/performance.md). The
  // fisheye keeps its radiance and applies the requested exposure and the sensor noise per
  // read. Memory: ~1.5 MB per RGB-D frame (+ truth), 12 bytes per fisheye pixel.
  std::int64_t prerender = 0;
  // Past its prerendered frames the fisheye serves them again from the first (frame i shows
  // the scene of i mod prerender, with its own time) instead of rendering live. For benches:
  // the fisheye runs on wall time at 50 frames/s, so below 50 RGB-D fps it outran the
  // prerendered frames and the sim's ray casting (~7-20 ms a frame) landed in the measurement,
  // slowing the pipeline further (docs/performance.md, 2026-11-27 evening).
  bool fisheye_repeat = false;
  // With fisheye_repeat: the fisheye prerenders and cycles only this many scenes (0: as many
  // as `prerender`), and keeps each exposed frame by (scene, exposure) so that a repeat costs
  // a copy instead of the sensor model (a noise draw per pixel and channel, ~5 CPU-ms a 50 Hz
  // fisheye frame on the bench host, 8 % of `perf`'s samples in `bench pipeline --prerender`:
  // the synthetic camera's work, which a real camera does in hardware). A multiple of 4 keeps
  // each scene on one bracket level (L, M, H, M), so the kept frames stay few. Repeated frames
  // then repeat their noise too.
  int fisheye_scenes = 0;
  // Stamp each prerendered RGB-D frame with the time it is read (CLOCK_MONOTONIC), as a
  // camera delivers, instead of its place on the 30 Hz sim clock. For benches that read
  // frames as fast as the pipeline takes them: on the sim clock a pipeline below 30 fps fell
  // behind the wall-time fisheye, and the light thread waited for poses that came late and
  // dropped most fisheye frames (docs/performance.md, 2026-11-28), so a slow host measured
  // less light work than a fast one.
  bool stamp_on_read = false;
  // A second moving occluder, a hand 0.25-0.45 m in front of the colour camera: closer than
  // the depth sensor's minimum range, so it has no depth (SimWorld::near_hand; the occlusion
  // evaluator's near-occluder protocol, docs/occlusion.md). Off by default: the frames
  // without it are unchanged.
  bool near_occluder = false;
  // > 1: colour pixels that straddle a depth edge are cast again with edge_samples^2 rays and
  // averaged (in radiance, before the camera's encoding), so silhouettes are mixed pixels as
  // a real camera's are; each such pixel's two layers go into FrameTruth::mixed_pixels (the
  // true foreground and fractional matte for the occlusion evaluator's composite error,
  // docs/occlusion.md). Off (1) by default: the frames without it are unchanged.
  int edge_samples = 1;
  // The frame's capture time (its timestamp, CLOCK_MONOTONIC) drawn into the bottom-left
  // corner of the colour image as a binary code (core/capture_stamp.hpp), for the
  // glass-to-glass latency bench (`probeless bench latency`, docs/outputs.md). Off by default:
  // the code covers 144 x 48 pixels of the picture.
  bool stamp = false;
  // A moving-object scene (`scene=box_slides`, ...; sim_moving_scene.hpp): its objects take
  // the arm's place in both cameras (the arm stays out, so the scene's object is the only
  // thing that moves). None by default: the frames without it are unchanged.
  MovingScene scene = MovingScene::None;
};

// Parses "seed=3,trajectory=static,fps=30,realtime=0,stall=60:120,..." (the part after
// "sim:"); throws std::invalid_argument naming the bad key. Keys: seed, trajectory
// (static|orbit|handheld|tabletop|calibration), fps (RGB-D), rgbd_fps, fisheye_fps, realtime,
// fisheye_realtime, fisheye_size, fisheye_bits, fisheye_fov, fisheye_ocam (an OCamCalib file),
// fisheye_ocam_model (ocam or kannala_brandt: that lens fitted), frames (max_frames), stall
// (BEGIN:END), stall_every (frames), truth, threads, start (seconds of world time at the first
// frame), near_occluder (0|1), edge_samples (1..8), stamp (0|1), scene (a moving-object scene's
// name, moving_scenes()).
SimOptions parse_sim_options(std::string_view spec);

// Rig from drivers/source.hpp (rgbd + fisheye + calibration, and its scene: object_anchor()
// and room_bounds()). Both sources share one immutable world and may be read concurrently
// from two threads.
Rig make_sim_rig(const SimOptions& options);

// Where virtual objects stand: the centre of the table top in the world frame (z up), and
// the table plane height.
Eigen::Vector3d object_anchor();
double table_top_height_m();
// The board of `board=1`, as `[world] marker` names it, and the world it anchors in the sim's
// world: origin at the centre of its face, x along its columns (world +x), y along world +y,
// z up (docs/tracking.md "World anchoring").
const char* board_spec();
Pose board_world_pose();
// Where FrameTruth::light is seen from: 10 cm above the anchor, the centre of a small object.
Eigen::Vector3d light_probe_position();
// The room's floor, walls and ceiling as an axis-aligned box in the world frame (metres):
// {lo, hi}. What a room proxy for light-capture parallax takes (docs/light-capture.md
// "Parallax"); the lamps are in the ceiling and the window in the back wall, on the box.
std::array<Eigen::Vector3d, 2> room_bounds();
// Sim radiance per unit of the HDR conversion's output for the sim's fisheye (docs/sim.md
// "The fisheye"): raw = black + L t g S with S = 600 DN per unit radiance per second at 0 dB
// on 12 bits and full scale white - black = 3839 DN (the 8-bit sensor scales both alike), and
// the conversion gives (raw - black) / (white - black) / (t g), so L = converted x 3839 / 600.
double fisheye_radiance_per_converted();

}  // namespace probeless::sim

#pragma once
// The GT-depth protocol on Middlebury stereo scenes (docs/occlusion.md "Protocols"): real
// colour and exact depth from the ground-truth disparity, a virtual plane patch and a sphere
// placed between the scene's foreground and background, the depth degraded by the Kinect
// noise model (core/depth_noise.hpp) with K seeds, the true matte from the clean depth.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

struct StereoScene {
  std::string name;
  ImageRGB8 colour;
  DepthImage depth_mm;  // clean; 0 = unknown ground truth
  double focal_px = 0;
};

// Directories under `root` (itself, or up to two levels down) that hold a scene in either
// layout: v2 (imL.png, groundtruth.png, info.txt) or 2014 (im0.png, disp0GT.pfm, calib.txt).
// Sorted by path. Throws ImageFileError naming `root` when it does not exist or has none.
std::vector<std::filesystem::path> find_middlebury_scenes(const std::filesystem::path& root);

// v2: d = groundtruth / scale (scale = first number of info.txt, 0 = unknown), z = k / d with
// k chosen so that the median depth is 1.5 m, focal 525 px scaled to the image width.
// 2014: z = baseline * f / (d + doffs) from calib.txt (parsed loosely), inf = unknown.
StereoScene load_middlebury_scene(const std::filesystem::path& dir);

enum class VirtualShape { Plane, Sphere };

// Virtual depth of the shape over the scene: 0 off the object. Its depths come from quantiles
// of the scene's known depth so real silhouettes cross it.
ImageF place_virtual_object(const StereoScene& scene, VirtualShape shape);

struct MiddleburyOptions {
  int frames = 8;  // K noisy frames of the static scene
  std::uint64_t seed = 1;
};

// Two cases per scene ("<scene>/plane", "<scene>/sphere"), each with K frames.
std::vector<EvalCase> middlebury_cases(const StereoScene& scene, const MiddleburyOptions& options);

}  // namespace probeless::eval

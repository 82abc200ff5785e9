#pragma once
// What sources deliver. Frames are plain values: a source fills them, the pipeline moves
// them through "latest frame" slots, nothing holds a pointer into a driver's buffers.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/cubemap.hpp"
#include "core/exposure.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "core/time.hpp"

namespace probeless {

// A colour pixel whose footprint straddles a silhouette: the camera saw near_coverage x near
// + (1 - near_coverage) x far, mixed in linear light before its encoding.
struct MixedPixel {
  std::uint32_t index = 0;                            // y * width + x
  float near_coverage = 0;                            // (0, 1)
  std::uint16_t near_mm = 0, far_mm = 0;              // each layer's mean depth
  std::array<std::uint8_t, 3> near_rgb{}, far_rgb{};  // each layer alone, encoded, noise-free
};

// Ground truth a synthetic or annotated source knows about a frame. Absent for live sensors.
struct FrameTruth {
  DepthImage clean_depth;                // noise-free depth, mm (0 = no surface in range)
  ImageGray8 occluder_mask;              // 255 where the moving occluder is visible
  std::optional<Pose> rig_pose;          // T_world_rig at the frame's timestamp
  std::shared_ptr<const Cubemap> light;  // radiance seen from the virtual object's position
  std::vector<MixedPixel> mixed_pixels;  // in index order; empty unless the sim's edge_samples > 1
};

// The forward RGB-D camera: colour and depth registered to the colour camera.
struct RgbdFrame {
  std::uint64_t sequence = 0;
  TimestampNs timestamp_ns = 0;
  ImageRGB8 colour;
  DepthImage depth;  // mm, 0 = unknown
  std::shared_ptr<const FrameTruth> truth;
};

// The upward fisheye: linear raw RGB (demosaiced), with the exposure it was taken at.
struct FisheyeFrame {
  std::uint64_t sequence = 0;
  TimestampNs timestamp_ns = 0;
  ImageRGB16 raw;      // linear sensor values in [0, 2^bit_depth - 1]
  int bit_depth = 12;  // 8 or 12 (values are not shifted to 16 bit)
  std::uint16_t black_level = 0;
  ExposureStamp exposure;
  std::shared_ptr<const FrameTruth> truth;
};

}  // namespace probeless

#pragma once
// Ray casts the synthetic room for one camera: radiance, and for the depth camera the depth
// along the optical axis and per-pixel flags. Work is split into 16 x 16 tiles, each with
// the primitives whose bounding spheres meet the cone of its rays, across a small pool of
// threads. When the camera and the lamps have not changed since the last frame, only tiles
// the moving arm touches (now or last frame) are cast again.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/camera/kannala_brandt.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"
#include "drivers/sim/sim_world.hpp"
#include "drivers/sim/worker_pool.hpp"

namespace probeless::sim {

// Pixel flags of the depth camera's view.
inline constexpr std::uint8_t kFlagOccluder = 1;  // the arm is the first hit
inline constexpr std::uint8_t kFlagNoDepth = 2;   // glass, black, mirror: no structured light

// A pixel whose footprint straddles a depth edge, cast again with n x n rays
// (SimRenderer::set_edge_samples): the rays split at the middle of their depth range into the
// near layer (the occluding side) and the far one. Its radiance is the mean of all rays,
// near_coverage x near + (1 - near_coverage) x far.
struct EdgePixel {
  std::int32_t index;  // y * width + x
  float near_coverage;
  Eigen::Vector3f near_radiance, far_radiance;
  float near_depth, far_depth;  // metres along the optical axis, each layer's mean
};

class SimRenderer {
 public:
  // An ideal pinhole (rays with camera-z = 1, so the hit distance is the depth). pool: the
  // threads to cast with (null: the caller's only); it must outlive the renderer.
  SimRenderer(std::shared_ptr<const SimWorld> world, int width, int height, double fx, double fy,
              double cx, double cy, WorkerPool* pool);
  // Any central camera model: one unit ray per pixel, from unproject().
  SimRenderer(std::shared_ptr<const SimWorld> world, const CameraModel& camera, WorkerPool* pool);

  // Casts the view from T_world_camera. with_depth: fill depth() and flags() (pinhole only).
  void render(const Pose& T_world_camera, int lamp_state, const Occluder* occluder,
              bool with_depth);

  const ImageRGBF& radiance() const { return radiance_; }
  const ImageF& depth() const { return depth_; }  // metres along the optical axis
  const ImageGray8& flags() const { return flags_; }
  // n > 1 (pinhole, with_depth renders only): after each render, pixels next to a depth jump
  // of more than kEdgeJump (relative) are cast again with n x n rays and averaged, and those
  // whose rays see two layers are listed in edge_pixels(), in index order. The depth and
  // flags stay the centre ray's (the depth sensor's own edge model is in depth_noise).
  void set_edge_samples(int n) { edge_samples_ = n; }
  const std::vector<EdgePixel>& edge_pixels() const { return edge_pixels_; }
  // 3 %: 3 cm at 1 m. A table at a grazing 35 deg changes depth by ~0.3 % a pixel at 640 x 480,
  // so only silhouettes count.
  static constexpr float kEdgeJump = 0.03f;
  int width() const { return width_; }
  int height() const { return height_; }
  // Tiles cast in the last render() (a static rig's frames re-cast only the arm's tiles).
  int tiles_cast() const { return tiles_cast_; }

 private:
  static constexpr int kTile = 16;
  static constexpr int kMaxPrims = 24;
  struct Tile {
    int x0, y0, x1, y1;
    Eigen::Vector3f axis;  // camera frame
    float cos_half, sin_half;
    bool any_valid = true;
  };
  struct TileList {
    std::uint8_t count = 0;
    bool dynamic = false;
    std::array<PrimRef, kMaxPrims> prims;
  };
  void build_tiles();
  void supersample_edges(const Eigen::Matrix3f& rotation, const Eigen::Vector3f& origin,
                         int lamp_state, const Occluder* occluder);
  void cast_tile(int index, const Eigen::Matrix3f& rotation, const Eigen::Vector3f& origin,
                 int lamp_state, const Occluder* occluder, bool with_depth);

  std::shared_ptr<const SimWorld> world_;
  int width_, height_;
  double fx_ = 0, fy_ = 0, cx_ = 0, cy_ = 0;
  std::vector<Eigen::Vector3f> table_;  // empty for the pinhole
  std::vector<std::uint8_t> valid_;
  std::vector<Tile> tiles_;
  std::vector<TileList> lists_;
  std::vector<std::uint8_t> had_dynamic_;
  WorkerPool* pool_;

  ImageRGBF radiance_;
  ImageF depth_;
  ImageGray8 flags_;
  bool have_last_ = false;
  Pose last_pose_;
  int last_lamp_state_ = -1;
  bool last_with_depth_ = false;
  int tiles_cast_ = 0;
  int edge_samples_ = 1;
  std::vector<EdgePixel> edge_pixels_;
};

}  // namespace probeless::sim

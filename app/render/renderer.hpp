#pragma once
// Renders virtual objects as the RGB-D colour camera would see them: an ideal pinhole with
// the camera's intrinsics, OpenCV pixel conventions, output top row first. Besides colour it
// writes the linear depth of every covered pixel in millimetres, the virtual depth that the
// occlusion stage compares with the sensor's (docs/rendering.md).
//
// Threading: the Renderer owns its EGL context (egl_context.hpp): construct it, render with
// it and destroy it on one thread, the pipeline's processing thread.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

#include "app/render/egl_context.hpp"
#include "app/render/gl_objects.hpp"
#include "app/render/mesh.hpp"
#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::render {

struct Material {
  // One shader pair per kind (app/render/shaders/); image-based kinds come later.
  enum class Shading { Lambert };
  Shading shading = Shading::Lambert;
  Eigen::Vector4f base_colour{1.f, 1.f, 1.f, 1.f};  // linear RGBA, times the mesh's colours
  bool double_sided = false;                        // draw back faces (open meshes, single quads)
};

struct VirtualObject {
  std::shared_ptr<const Mesh> mesh;
  Pose T_world_object;
  double scale = 1.0;  // uniform, > 0
  Material material;
};

struct Camera {
  PinholeIntrinsics intrinsics;  // distortion is not rendered: undistort the real image
  Pose T_world_camera;           // camera frame: OpenCV (x right, y down, z forward)
};

struct RenderTarget {
  ImageRGBA8 color;  // gamma 2.2 display colour, alpha = coverage (255 or 0)
  ImageF depth_mm;   // distance along the optical axis (camera z), mm; 0 where no object
};

struct RendererConfig {
  double near_m = 0.05;  // clip planes along camera z
  double far_m = 20.0;
  // Towards the light, world frame (z up): high and to one side, so that shapes read.
  // A placeholder until image-based lighting takes the light from the fisheye.
  Eigen::Vector3d light_direction_world{-0.5, -0.3, 0.8};
  float ambient = 0.3f;
};

// The OpenGL projection for pinhole intrinsics, exactly (docs/rendering.md derives it): a
// camera-frame point lands in the window at (u + 0.5, v + 0.5), where (u, v) is its OpenCV
// pixel, so glReadPixels' first row is the image's top row. Window y therefore runs down:
// faces that are counter-clockwise seen from outside come out clockwise on screen.
Eigen::Matrix4d projection_from_intrinsics(const PinholeIntrinsics& k, double near_m, double far_m);

// T_world_camera of an OpenCV camera at `eye` looking at `target`, image up towards `up`
// (world z by default). Throws std::invalid_argument when the view is along `up`.
Pose camera_look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

class Renderer {
 public:
  // Creates the EGL context (throws EglError when there is none) and compiles the shaders.
  explicit Renderer(const RendererConfig& config = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws `objects` and reads colour and depth back into `out`, whose images are resized only
  // when the intrinsics' size changes. Meshes are uploaded once and kept while their
  // shared_ptr lives.
  void render(const Camera& camera, const std::vector<VirtualObject>& objects, RenderTarget& out);

  const EglContext& context() const { return *context_; }
  const RendererConfig& config() const { return config_; }

 private:
  struct GpuMesh;
  struct Program;
  static std::unique_ptr<Program> make_program(Material::Shading shading);
  const GpuMesh& upload(const std::shared_ptr<const Mesh>& mesh);
  void resize(int width, int height);
  void read_back(RenderTarget& out);

  RendererConfig config_;
  std::unique_ptr<EglContext> context_;
  std::vector<std::unique_ptr<Program>> programs_;  // indexed by Material::Shading
  std::map<const Mesh*, std::unique_ptr<GpuMesh>> meshes_;
  int width_ = 0, height_ = 0;
  GlFramebuffer framebuffer_;
  GlRenderbuffer colour_buffer_, depth_mm_buffer_, z_buffer_;
  bool read_depth_as_red_ = false;  // else as RGBA floats through depth_scratch_
  std::vector<float> depth_scratch_;
};

}  // namespace probeless::render

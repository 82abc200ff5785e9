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
#include "app/render/environment.hpp"
#include "app/render/environment_map.hpp"
#include "app/render/gl_objects.hpp"
#include "app/render/mesh.hpp"
#include "app/render/screen_bounds.hpp"
#include "core/camera/pinhole.hpp"
#include "core/image.hpp"
#include "core/pose.hpp"

namespace probeless::render {

struct Material {
  // One shader per kind (app/render/shaders/<kind>.hpp; docs/rendering.md "Materials").
  // Lambert needs nothing else; every other kind needs the object's environment, and
  // PrtDiffuse also the mesh's transfer vectors.
  enum class Shading {
    Lambert,     // placeholder: one fixed light plus ambient (RendererConfig)
    Mirror,      // ideal mirror: the reflected ray's radiance x base colour
    RoughMetal,  // GGX metal, split sum over the prefiltered levels; base colour = F0
    Refraction,  // glass / water: one refraction at the front face, Fresnel mix with reflection
    ShDiffuse,   // Lambertian, unshadowed: SH irradiance (R&H 2001); base colour = albedo
    PrtDiffuse,  // Lambertian, self-shadowed: per-vertex SH transfer (Mesh::prt_transfer)
    // Differential rendering's receiver (Debevec 1998; thesis ch. 6): a mesh on the real
    // ground whose transfer is (with objects - without), so it writes the signed radiance
    // change albedo * sum_i dT_i L_i with coverage 0 (the HDR compositor's "sum" category).
    // Only the float target draws it: the display target has no way to say "add".
    GroundShadow,
  };
  static constexpr int kShadingCount = 7;

  Shading shading = Shading::Lambert;
  // Linear RGBA, times the mesh's colours: albedo (Lambert, diffuse kinds), reflectance
  // (Mirror), F0 (RoughMetal), transmission tint (Refraction).
  Eigen::Vector4f base_colour{1.f, 1.f, 1.f, 1.f};
  bool double_sided = false;  // draw back faces (open meshes, single quads)
  float roughness = 0.5f;     // RoughMetal: perceptual roughness in [0, 1], GGX alpha = r^2
  float ior = 1.5f;           // Refraction: index of refraction (glass 1.5, water 1.33), > 0
  // GroundShadow: its depth is written this much nearer the camera than the mesh, so that the
  // real surface it lies on counts as behind it in the occlusion test despite sensor noise
  // (50 mm: several sigma of the Kinect-like noise at 2 m, docs/sim.md), while a hand above
  // the table still hides the shadow.
  float depth_offset_mm = 0.f;
};

struct VirtualObject {
  std::shared_ptr<const Mesh> mesh;
  Pose T_world_object;
  double scale = 1.0;  // uniform, > 0
  Material material;
  // The light around the object (world frame): needed by every shading but Lambert. Shared
  // between objects lit by the same keyframe; uploaded and prefiltered once per instance.
  std::shared_ptr<const Environment> environment;
};

struct Camera {
  PinholeIntrinsics intrinsics;  // distortion is not rendered: undistort the real image
  Pose T_world_camera;           // camera frame: OpenCV (x right, y down, z forward)
};

enum class ColourOutput {
  Display8,     // `color`: gamma 2.2 of radiance x exposure, alpha = coverage (255 or 0)
  LinearFloat,  // `radiance`: linear radiance (RGBA32F target), alpha = coverage (1 or 0)
};

struct RenderTarget {
  ColourOutput output = ColourOutput::Display8;  // which colour image render() writes
  float exposure = 1.f;  // Display8 only: radiance is scaled by this before gamma and clamping
  ImageRGBA8 colour;     // Display8; left as it is under LinearFloat
  ImageRGBAF radiance;   // LinearFloat (the HDR compositor's input); left as it is otherwise
  ImageF depth_mm;       // distance along the optical axis (camera z), mm; 0 where no object
  // Where the last render() may have left an object in the colour image of `drawn_output` and
  // in depth_mm: they are zero outside. render() clears and reads back only the objects'
  // projected bounds (RendererConfig::scissor) and zeroes what the previous frame drew outside.
  PixelRect drawn;
  ColourOutput drawn_output = ColourOutput::Display8;
};

struct RendererConfig {
  double near_m = 0.05;  // clip planes along camera z
  double far_m = 20.0;
  // Towards the light, world frame (z up): high and to one side, so that shapes read.
  // A placeholder until image-based lighting takes the light from the fisheye.
  Eigen::Vector3d light_direction_world{-0.5, -0.3, 0.8};
  float ambient = 0.3f;
  PrefilterConfig prefilter;  // the rough metal's prefiltered levels (environment_map.hpp)
  // Clear, draw and read back only the pixels the objects' bounding boxes project to
  // (screen_bounds.hpp); false: the whole image every frame (the same pictures, bit for bit;
  // the tests compare the two).
  bool scissor = true;
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

  // Draws `objects` and reads colour (out.output says which image) and depth back into `out`,
  // whose images are resized only when the intrinsics' size changes. Meshes and environments
  // are uploaded (environments prefiltered) on first use and kept while their shared_ptr
  // lives. Throws std::invalid_argument for an object without mesh, with a bad scale, or
  // without the environment or transfer its material needs.
  void render(const Camera& camera, const std::vector<VirtualObject>& objects, RenderTarget& out);

  // Uploads and prefilters `environment` now instead of at its first render(), so that the
  // cost lands where the caller chooses (right after a light update, say). Does not wait.
  void prepare(const std::shared_ptr<const Environment>& environment);
  // A level of an environment's radiance or specular texture as radiance (tests, debugging;
  // blocks).
  Cubemap read_environment(const std::shared_ptr<const Environment>& environment,
                           EnvironmentLayer layer, int level);
  // Waits until the GL work issued so far has finished (timing).
  void finish();

  const EglContext& context() const { return *context_; }
  const RendererConfig& config() const { return config_; }

 private:
  struct GpuMesh;
  struct GpuEnvironment;
  struct Program;
  static std::unique_ptr<Program> make_program(Material::Shading shading);
  const Program& program(Material::Shading shading);
  const GpuMesh& upload(const std::shared_ptr<const Mesh>& mesh);
  const EnvironmentTexture& upload(const std::shared_ptr<const Environment>& environment);
  GLuint split_sum_texture();
  void set_material_uniforms(const Program& prog, const VirtualObject& object,
                             const EnvironmentTexture* environment);
  void resize(int width, int height, ColourOutput output);
  // Forgets meshes and environments whose shared_ptr is gone (keeping one texture's storage).
  void drop_expired();
  // The pixels `objects` can cover from `camera` (the whole image without the scissor).
  PixelRect drawn_pixels(const Camera& camera, const std::vector<VirtualObject>& objects,
                         ColourOutput output);
  void read_back(RenderTarget& out, const PixelRect& rect);

  RendererConfig config_;
  std::unique_ptr<EglContext> context_;
  std::vector<std::unique_ptr<Program>> programs_;  // by Material::Shading, made on first use
  std::map<const Mesh*, std::unique_ptr<GpuMesh>> meshes_;
  std::unique_ptr<EnvironmentPrefilter> prefilter_;
  std::map<const Environment*, std::unique_ptr<GpuEnvironment>> environments_;
  EnvironmentTexture spare_environment_;  // an expired one's storage, reused by the next
  GlTexture split_sum_;                   // RG16F table (split_sum.hpp), made on first use
  int width_ = 0, height_ = 0;
  ColourOutput output_ = ColourOutput::Display8;
  GlFramebuffer framebuffer_;
  GlRenderbuffer colour_buffer_, depth_mm_buffer_, z_buffer_;
  bool read_depth_as_red_ = false;  // else as RGBA floats through depth_scratch_
  ImageRGBAF depth_scratch_;
};

}  // namespace probeless::render

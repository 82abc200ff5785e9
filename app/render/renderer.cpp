#include "app/render/renderer.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "app/render/renderer_internal.hpp"
#include "app/render/sh_uniforms.hpp"

namespace probeless::render {

namespace {

static_assert(static_cast<int>(Material::Shading::GroundShadow) + 1 == Material::kShadingCount,
              "kShadingCount counts the Shading enumerators");

bool needs_environment(Material::Shading s) {
  return s != Material::Shading::Lambert;
}

// The ground shadow is a signed change of the real pixel: only the HDR compositor applies it.
bool drawn_into(const VirtualObject& object, ColourOutput output) {
  return object.material.shading != Material::Shading::GroundShadow ||
         output == ColourOutput::LinearFloat;
}

// Composed in double so that a world far from the origin keeps its precision.
Eigen::Matrix4d camera_from(const Pose& T_camera_world, const VirtualObject& object) {
  Eigen::Matrix4d m = (T_camera_world * object.T_world_object).matrix();
  m.topLeftCorner<3, 3>() *= object.scale;
  return m;
}

// Zeroes the pixels of `stale` that are not in `fresh` (the previous frame's object outside
// this frame's bounds), row span by row span.
template <typename T, int C>
void clear_outside(Image<T, C>& image, const PixelRect& stale, const PixelRect& fresh) {
  auto zero = [&](int y, int x0, int x1) {
    if (x1 > x0) std::fill(image.row(y) + x0 * C, image.row(y) + x1 * C, T{});
  };
  for (int y = stale.y0; y < stale.y1; ++y) {
    if (!fresh.contains_row(y)) {
      zero(y, stale.x0, stale.x1);
      continue;
    }
    zero(y, stale.x0, std::min(stale.x1, fresh.x0));
    zero(y, std::max(stale.x0, fresh.x1), stale.x1);
  }
}

// glReadPixels of `rect` into the same pixels of `image` (GL's rows are the image's rows:
// projection_from_intrinsics).
template <typename T, int C>
void read_rect(Image<T, C>& image, const PixelRect& rect, GLenum format, GLenum type) {
  if (rect.empty()) return;
  glPixelStorei(GL_PACK_ROW_LENGTH, image.width());
  glReadPixels(rect.x0, rect.y0, rect.width(), rect.height(), format, type,
               image.row(rect.y0) + rect.x0 * C);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);  // the prefilter's read-back shares the context
}

}  // namespace

Eigen::Matrix4d projection_from_intrinsics(const PinholeIntrinsics& k, double n, double f) {
  if (!(n > 0 && f > n)) throw std::invalid_argument("projection: need 0 < near < far");
  const double w = k.width, h = k.height;
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  // x_ndc = 2 (u + 0.5) / W - 1 with u = fx x / z + cx, and likewise y from v, over w = z.
  p(0, 0) = 2 * k.fx / w;
  p(0, 2) = (2 * k.cx + 1) / w - 1;
  p(1, 1) = 2 * k.fy / h;
  p(1, 2) = (2 * k.cy + 1) / h - 1;
  // z_ndc = -1 at z = near, +1 at z = far (only the z test uses it; depth output is linear).
  p(2, 2) = (f + n) / (f - n);
  p(2, 3) = -2 * f * n / (f - n);
  p(3, 2) = 1;
  return p;
}

Pose camera_look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - eye).normalized();  // forward
  Eigen::Vector3d x = z.cross(up);                        // right = forward x up
  if (!(x.norm() > 1e-9)) throw std::invalid_argument("camera_look_at: view along up");
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);  // down
  Eigen::Matrix3d r;
  r << x, y, z;
  Pose pose;
  pose.rotation = Eigen::Quaterniond(r).normalized();
  pose.translation = eye;
  return pose;
}

Renderer::Renderer(const RendererConfig& config)
    : config_(config), context_(std::make_unique<EglContext>()) {
  if (!(config_.near_m > 0 && config_.far_m > config_.near_m))
    throw std::invalid_argument("renderer: need 0 < near_m < far_m");
  if (!context_->has_gl_extension("GL_EXT_color_buffer_float"))
    throw GlError("renderer: " + context_->renderer() +
                  " lacks GL_EXT_color_buffer_float (needed for the R32F depth output)");
  programs_.resize(Material::kShadingCount);
  programs_[0] = make_program(Material::Shading::Lambert);  // the default: fail early
  framebuffer_ = make_framebuffer();
  check_gl("renderer setup");
}

Renderer::~Renderer() {
  try {
    context_->make_current();  // the GL objects below are deleted in this context
  } catch (const std::exception& e) {
    spdlog::error("render: {} (GL objects leak)", e.what());
  }
}

const Renderer::Program& Renderer::program(Material::Shading shading) {
  auto& slot = programs_.at(static_cast<std::size_t>(shading));
  if (!slot) slot = make_program(shading);  // compiled on first use: most scenes use one or two
  return *slot;
}

void Renderer::resize(int width, int height, ColourOutput output) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("renderer: image size must be positive, got " +
                                std::to_string(width) + "x" + std::to_string(height));
  auto storage = [&](GlRenderbuffer& rb, GLenum format) {
    rb = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, rb.get());
    glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
  };
  // RGBA32F rather than 16F for the HDR target: the compositor reads floats anyway, and
  // lamps in the capture's units can exceed half's 65504.
  storage(colour_buffer_, output == ColourOutput::LinearFloat ? GL_RGBA32F : GL_RGBA8);
  storage(depth_mm_buffer_, GL_R32F);
  storage(z_buffer_, GL_DEPTH_COMPONENT32F);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                            colour_buffer_.get());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER,
                            depth_mm_buffer_.get());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, z_buffer_.get());
  const GLenum draw[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, draw);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("renderer: framebuffer incomplete (status 0x" + std::to_string(status) + ")");
  // GLES 3 always reads floats as RGBA; a single RED channel is the implementation's choice.
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  GLint format = 0, type = 0;
  glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_FORMAT, &format);
  glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_TYPE, &type);
  read_depth_as_red_ = format == GL_RED && type == GL_FLOAT;
  if (read_depth_as_red_)
    depth_scratch_ = {};
  else
    depth_scratch_ = ImageRGBAF(width, height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  check_gl("renderer: framebuffer setup");
  width_ = width;
  height_ = height;
  output_ = output;
  spdlog::debug("render: framebuffer {}x{} {}, depth read as {}", width, height,
                output == ColourOutput::LinearFloat ? "RGBA32F" : "RGBA8",
                read_depth_as_red_ ? "R32F" : "RGBA32F");
}

void Renderer::render(const Camera& camera, const std::vector<VirtualObject>& objects,
                      RenderTarget& out) {
  context_->make_current();
  const PinholeIntrinsics& k = camera.intrinsics;
  if (k.width != width_ || k.height != height_ || out.output != output_)
    resize(k.width, k.height, out.output);
  drop_expired();

  // Uploads and prefilter passes first: they use framebuffers and state of their own.
  std::vector<const EnvironmentTexture*> lights(objects.size(), nullptr);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const VirtualObject& object = objects[i];
    if (!object.mesh) throw std::invalid_argument("renderer: a virtual object has no mesh");
    const std::string& name = object.mesh->name;
    if (!(object.scale > 0))
      throw std::invalid_argument("renderer: object scale must be > 0 (mesh '" + name + "')");
    upload(object.mesh);
    const Material::Shading shading = object.material.shading;
    if (needs_environment(shading)) {
      if (!object.environment)
        throw std::invalid_argument("renderer: mesh '" + name +
                                    "': its material needs an environment");
      lights[i] = &upload(object.environment);
    }
    if ((shading == Material::Shading::PrtDiffuse || shading == Material::Shading::GroundShadow) &&
        object.mesh->prt_transfer.empty())
      throw std::invalid_argument("renderer: mesh '" + name +
                                  "': the PRT material needs Mesh::prt_transfer");
    if (shading == Material::Shading::Refraction && !(object.material.ior > 0))
      throw std::invalid_argument("renderer: mesh '" + name + "': ior must be > 0");
  }

  const PixelRect rect = drawn_pixels(camera, objects, out.output);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glViewport(0, 0, width_, height_);
  // The clears and the draws stay inside the objects' bounds: what lies outside is never read.
  glEnable(GL_SCISSOR_TEST);
  glScissor(rect.x0, rect.y0, rect.width(), rect.height());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glFrontFace(GL_CW);  // window y runs down (see projection_from_intrinsics)
  glCullFace(GL_BACK);
  const GLfloat zero[4] = {0, 0, 0, 0};
  const GLfloat far_depth = 1.f;
  glClearBufferfv(GL_COLOR, 0, zero);
  glClearBufferfv(GL_COLOR, 1, zero);
  glClearBufferfv(GL_DEPTH, 0, &far_depth);

  const Eigen::Matrix4f projection =
      projection_from_intrinsics(k, config_.near_m, config_.far_m).cast<float>();
  const Eigen::Vector3f light = config_.light_direction_world.normalized().cast<float>();
  const Pose T_camera_world = camera.T_world_camera.inverse();
  const Eigen::Matrix3f world_from_camera =
      camera.T_world_camera.rotation.toRotationMatrix().cast<float>();
  const Program* bound = nullptr;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const VirtualObject& object = objects[i];
    if (!drawn_into(object, out.output)) continue;
    const GpuMesh& gpu = upload(object.mesh);
    const Program& prog = program(object.material.shading);
    if (&prog != bound) {
      glUseProgram(prog.program.get());
      glUniformMatrix4fv(prog.projection, 1, GL_FALSE, projection.data());
      glUniformMatrix3fv(prog.world_from_camera, 1, GL_FALSE, world_from_camera.data());
      glUniform1i(prog.linear_output, out.output == ColourOutput::LinearFloat);
      glUniform1f(prog.exposure, out.exposure);
      glUniform3fv(prog.light_dir, 1, light.data());
      glUniform1f(prog.ambient, config_.ambient);
      bound = &prog;
    }
    const Eigen::Matrix4f m = camera_from(T_camera_world, object).cast<float>();
    const Eigen::Matrix3f r = object.T_world_object.rotation.toRotationMatrix().cast<float>();
    const Eigen::Vector4f colour = object.material.base_colour.cwiseProduct(gpu.base_colour);
    glUniformMatrix4fv(prog.camera_from_object, 1, GL_FALSE, m.data());
    glUniformMatrix3fv(prog.world_from_object, 1, GL_FALSE, r.data());
    glUniform4fv(prog.base_colour, 1, colour.data());
    set_material_uniforms(prog, object, lights[i]);
    if (object.material.double_sided)
      glDisable(GL_CULL_FACE);
    else
      glEnable(GL_CULL_FACE);
    glBindVertexArray(gpu.vao.get());
    if (!gpu.colours) glVertexAttrib4f(kColour, 1.f, 1.f, 1.f, 1.f);
    glDrawElements(GL_TRIANGLES, gpu.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_SCISSOR_TEST);  // the prefilter passes share the context
  read_back(out, rect);
  check_gl("renderer: render");
}

void Renderer::set_material_uniforms(const Program& prog, const VirtualObject& object,
                                     const EnvironmentTexture* environment) {
  const Material& material = object.material;
  switch (material.shading) {
    case Material::Shading::Lambert:
      return;
    case Material::Shading::PrtDiffuse:
    case Material::Shading::GroundShadow: {
      const std::array<float, 84> l =
          prt_light(object.environment->sh, object.T_world_object.rotation.toRotationMatrix());
      glUniform4fv(prog.light, 21, l.data());
      glUniform1f(prog.depth_offset_mm, material.depth_offset_mm);
      return;
    }
    case Material::Shading::RoughMetal:
      glActiveTexture(GL_TEXTURE0 + kSplitSumUnit);
      glBindTexture(GL_TEXTURE_2D, split_sum_texture());
      glActiveTexture(GL_TEXTURE0 + kSpecularUnit);
      glBindTexture(GL_TEXTURE_CUBE_MAP, environment->specular.get());
      glUniform1f(prog.roughness, material.roughness);
      break;
    case Material::Shading::Refraction:
      glUniform1f(prog.ior, material.ior);
      break;
    case Material::Shading::Mirror:
    case Material::Shading::ShDiffuse:
      break;
  }
  glActiveTexture(GL_TEXTURE0 + kEnvironmentUnit);
  glBindTexture(GL_TEXTURE_CUBE_MAP, environment->radiance.get());
  glUniform1f(prog.environment_scale, environment->scale);
  glUniform1f(prog.max_lod, static_cast<float>(environment->specular_levels - 1));
  if (prog.irradiance >= 0) {
    const std::array<Eigen::Matrix4f, 3> m = irradiance_matrices(object.environment->sh);
    float packed[48];
    for (std::size_t c = 0; c < 3; ++c) std::copy_n(m[c].data(), 16, packed + 16 * c);
    glUniformMatrix4fv(prog.irradiance, 3, GL_FALSE, packed);
  }
}

PixelRect Renderer::drawn_pixels(const Camera& camera, const std::vector<VirtualObject>& objects,
                                 ColourOutput output) {
  const PixelRect whole = PixelRect::whole(width_, height_);
  if (!config_.scissor) return whole;
  const Pose T_camera_world = camera.T_world_camera.inverse();
  PixelRect rect;
  for (const VirtualObject& object : objects) {
    if (!drawn_into(object, output)) continue;
    const GpuMesh& gpu = upload(object.mesh);
    rect = unite(rect, projected_box(camera.intrinsics, camera_from(T_camera_world, object), gpu.lo,
                                     gpu.hi, config_.near_m));
    if (rect == whole) break;
  }
  return rect;
}

void Renderer::read_back(RenderTarget& out, const PixelRect& rect) {
  // What may be non-zero in each image before this frame: the last frame's rectangle in the
  // depth; in the colour image too if the last frame wrote this one, else all of it (that
  // output's last rectangle is not kept); nothing in an image allocated here (zeros).
  PixelRect depth_stale = out.drawn;
  PixelRect colour_stale =
      out.drawn_output == out.output ? out.drawn : PixelRect::whole(width_, height_);
  auto fit = [&](auto& image, PixelRect& stale) {
    if (image.width() == width_ && image.height() == height_) return;
    image = std::remove_reference_t<decltype(image)>(width_, height_);
    stale = {};
  };
  fit(out.depth_mm, depth_stale);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  if (out.output == ColourOutput::LinearFloat) {
    fit(out.radiance, colour_stale);
    clear_outside(out.radiance, colour_stale, rect);
    read_rect(out.radiance, rect, GL_RGBA, GL_FLOAT);
  } else {
    fit(out.colour, colour_stale);
    clear_outside(out.colour, colour_stale, rect);
    read_rect(out.colour, rect, GL_RGBA, GL_UNSIGNED_BYTE);
  }
  clear_outside(out.depth_mm, depth_stale, rect);
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  if (read_depth_as_red_) {
    read_rect(out.depth_mm, rect, GL_RED, GL_FLOAT);
  } else if (!rect.empty()) {
    // RGBA floats through the scratch image, red kept.
    read_rect(depth_scratch_, rect, GL_RGBA, GL_FLOAT);
    for (int y = rect.y0; y < rect.y1; ++y)
      for (int x = rect.x0; x < rect.x1; ++x) out.depth_mm.at(x, y) = depth_scratch_.at(x, y, 0);
  }
  out.drawn = rect;
  out.drawn_output = out.output;
}

}  // namespace probeless::render

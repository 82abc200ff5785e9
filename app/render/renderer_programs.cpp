#include <string>

#include "app/render/renderer_internal.hpp"
#include "app/render/shaders/common.hpp"
#include "app/render/shaders/lambert.hpp"
#include "app/render/shaders/mirror.hpp"
#include "app/render/shaders/prt_diffuse.hpp"
#include "app/render/shaders/refraction.hpp"
#include "app/render/shaders/rough_metal.hpp"
#include "app/render/shaders/sh_diffuse.hpp"
#include "app/render/split_sum.hpp"

namespace probeless::render {

std::unique_ptr<Renderer::Program> Renderer::make_program(Material::Shading shading) {
  using S = Material::Shading;
  std::string_view vertex = shaders::material_vertex, body, name;
  bool image_based = true;
  switch (shading) {
    case S::Lambert:
      name = "lambert";
      body = shaders::lambert_fragment;
      image_based = false;
      break;
    case S::Mirror:
      name = "mirror";
      body = shaders::mirror_fragment;
      break;
    case S::RoughMetal:
      name = "rough_metal";
      body = shaders::rough_metal_fragment;
      break;
    case S::Refraction:
      name = "refraction";
      body = shaders::refraction_fragment;
      break;
    case S::ShDiffuse:
      name = "sh_diffuse";
      body = shaders::sh_diffuse_fragment;
      break;
    case S::PrtDiffuse:
      name = "prt_diffuse";
      vertex = shaders::prt_vertex;
      body = shaders::prt_diffuse_fragment;
      image_based = false;  // reads the SH only, through its vertex shader
      break;
    case S::GroundShadow:
      name = "ground_shadow";
      vertex = shaders::prt_vertex;
      body = shaders::ground_shadow_fragment;
      image_based = false;
      break;
  }
  std::string fragment(shaders::fragment_prelude);
  if (image_based) fragment += shaders::environment_functions;
  fragment += body;

  auto p = std::make_unique<Program>();
  p->program = link_program(name, vertex, fragment);
  const GLuint id = p->program.get();
  auto required = [&](const char* uniform) {
    const GLint loc = glGetUniformLocation(id, uniform);
    if (loc < 0) throw GlError(std::string(name) + " shader lacks uniform " + uniform);
    return loc;
  };
  auto optional = [&](const char* uniform) { return glGetUniformLocation(id, uniform); };
  p->camera_from_object = required("u_camera_from_object");
  p->projection = required("u_projection");
  p->world_from_object = optional("u_world_from_object");  // unused (optimised out) by some
  p->world_from_camera = optional("u_world_from_camera");
  p->base_colour = required("u_base_colour");
  p->linear_output = required("u_linear_output");
  p->exposure = required("u_exposure");
  p->light_dir = optional("u_light_dir_world");
  p->ambient = optional("u_ambient");
  p->environment_scale = optional("u_environment_scale");
  p->max_lod = optional("u_max_lod");
  p->irradiance = optional("u_irradiance");
  p->roughness = optional("u_roughness");
  p->ior = optional("u_ior");
  p->light = optional("u_light");
  p->depth_offset_mm = optional("u_depth_offset_mm");
  // Samplers are bound to fixed units once.
  glUseProgram(id);
  if (const GLint env = optional("u_environment"); env >= 0) glUniform1i(env, kEnvironmentUnit);
  if (const GLint lut = optional("u_split_sum"); lut >= 0) glUniform1i(lut, kSplitSumUnit);
  if (const GLint spec = optional("u_specular"); spec >= 0) glUniform1i(spec, kSpecularUnit);
  glUseProgram(0);
  check_gl("renderer: program set-up");
  return p;
}

GlTexture make_split_sum_texture() {
  const std::vector<float> table = make_split_sum_table(kSplitSumSize);
  GlTexture t = make_texture();
  glBindTexture(GL_TEXTURE_2D, t.get());
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RG16F, kSplitSumSize, kSplitSumSize);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kSplitSumSize, kSplitSumSize, GL_RG, GL_FLOAT,
                  table.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check_gl("renderer: split-sum table");
  return t;
}

}  // namespace probeless::render

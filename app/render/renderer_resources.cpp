// Uploads of meshes and environments (with the prefilter), kept while their shared_ptr lives.
#include <stdexcept>
#include <tuple>
#include <vector>

#include "app/render/renderer_internal.hpp"

namespace probeless::render {

const Renderer::GpuMesh& Renderer::upload(const std::shared_ptr<const Mesh>& mesh) {
  auto it = meshes_.find(mesh.get());
  if (it != meshes_.end() && it->second->source.lock() == mesh) return *it->second;
  mesh->validate();
  auto gpu = std::make_unique<GpuMesh>();
  gpu->source = mesh;
  gpu->vao = make_vertex_array();
  gpu->vertices = make_buffer();
  gpu->indices = make_buffer();
  gpu->index_count = static_cast<GLsizei>(mesh->indices.size());
  gpu->base_colour = mesh->base_colour;
  std::tie(gpu->lo, gpu->hi) = mesh->bounds();
  std::vector<float> interleaved;
  interleaved.reserve(mesh->positions.size() * 6);
  for (std::size_t i = 0; i < mesh->positions.size(); ++i) {
    interleaved.insert(interleaved.end(), mesh->positions[i].data(), mesh->positions[i].data() + 3);
    interleaved.insert(interleaved.end(), mesh->normals[i].data(), mesh->normals[i].data() + 3);
  }
  glBindVertexArray(gpu->vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, gpu->vertices.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
               interleaved.data(), GL_STATIC_DRAW);
  const GLsizei stride = 6 * sizeof(float);
  glEnableVertexAttribArray(kPosition);
  glVertexAttribPointer(kPosition, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(kNormal);
  glVertexAttribPointer(kNormal, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  if (!mesh->colours.empty()) {
    gpu->colours = make_buffer();
    glBindBuffer(GL_ARRAY_BUFFER, gpu->colours.get());
    glBufferData(GL_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh->colours.size() * sizeof(Eigen::Vector4f)),
                 mesh->colours.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(kColour);
    glVertexAttribPointer(kColour, 4, GL_FLOAT, GL_FALSE, sizeof(Eigen::Vector4f), nullptr);
  }
  if (!mesh->prt_transfer.empty()) {
    // As the baker wrote it, 25 floats per vertex: six vec4 attributes and a float.
    gpu->transfer = make_buffer();
    glBindBuffer(GL_ARRAY_BUFFER, gpu->transfer.get());
    glBufferData(GL_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh->prt_transfer.size() * sizeof(float)),
                 mesh->prt_transfer.data(), GL_STATIC_DRAW);
    const auto transfer_stride = static_cast<GLsizei>(kPrtCoefficients * sizeof(float));
    for (GLuint k = 0; k < 7; ++k) {
      glEnableVertexAttribArray(kTransfer + k);
      glVertexAttribPointer(kTransfer + k, k < 6 ? 4 : 1, GL_FLOAT, GL_FALSE, transfer_stride,
                            reinterpret_cast<const void*>(4 * k * sizeof(float)));
    }
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu->indices.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(mesh->indices.size() * sizeof(std::uint32_t)),
               mesh->indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  check_gl("renderer: mesh upload");
  auto& slot = meshes_[mesh.get()];
  slot = std::move(gpu);
  return *slot;
}

const EnvironmentTexture& Renderer::upload(const std::shared_ptr<const Environment>& environment) {
  auto it = environments_.find(environment.get());
  if (it != environments_.end() && it->second->source.lock() == environment)
    return it->second->texture;
  if (!prefilter_) prefilter_ = std::make_unique<EnvironmentPrefilter>(config_.prefilter);
  auto gpu = std::make_unique<GpuEnvironment>();
  gpu->source = environment;
  // A light update replaces the environment every few frames: reuse the storage of the one
  // it replaced rather than allocate a new texture each time.
  if (spare_environment_.face_size == environment->face_size()) {
    gpu->texture = std::move(spare_environment_);
    spare_environment_ = {};
  }
  prefilter_->update(*environment, gpu->texture);
  auto& slot = environments_[environment.get()];
  slot = std::move(gpu);
  return slot->texture;
}

void Renderer::drop_expired() {
  std::erase_if(meshes_, [](const auto& entry) { return entry.second->source.expired(); });
  std::erase_if(environments_, [&](auto& entry) {
    if (!entry.second->source.expired()) return false;
    spare_environment_ = std::move(entry.second->texture);
    return true;
  });
}

void Renderer::prepare(const std::shared_ptr<const Environment>& environment) {
  if (!environment) throw std::invalid_argument("renderer: prepare() needs an environment");
  context_->make_current();
  drop_expired();
  upload(environment);
}

Cubemap Renderer::read_environment(const std::shared_ptr<const Environment>& environment,
                                   EnvironmentLayer layer, int level) {
  prepare(environment);
  return read_environment_level(upload(environment), layer, level);
}

void Renderer::finish() {
  context_->make_current();
  glFinish();
}

GLuint Renderer::split_sum_texture() {
  if (!split_sum_) split_sum_ = make_split_sum_texture();
  return split_sum_.get();
}

}  // namespace probeless::render

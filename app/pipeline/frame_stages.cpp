#include "app/pipeline/frame_stages.hpp"

#include <algorithm>

#include "app/pipeline/scene_objects.hpp"

namespace probeless {

RenderStage::RenderStage(std::vector<render::VirtualObject> objects, PinholeIntrinsics intrinsics,
                         LightSource light)
    : renderer_(renderer_config_for(objects)),
      objects_(std::move(objects)),
      placeholders_(placeholder_objects(objects_)),
      intrinsics_(intrinsics),
      light_(std::move(light)) {
  for (const auto& o : objects_)
    image_based_ = image_based_ || o.material.shading != render::Material::Shading::Lambert;
}

void RenderStage::process(FrameWork& work) {
  const std::shared_ptr<const LightSnapshot> snap =
      image_based_ && light_ ? light_() : std::shared_ptr<const LightSnapshot>{};
  work.hdr = snap && snap->colour_exposure_valid;
  if (!work.hdr) {
    work.virtual_view.output = render::ColourOutput::Display8;
    renderer_.render({intrinsics_, work.T_world_camera}, placeholders_, work.virtual_view);
    return;
  }
  if (snap->version != light_version_) {
    // A new keyframe copy: a new Environment, uploaded and prefiltered once for all objects.
    auto env = std::make_shared<const render::Environment>(
        render::make_environment(snap->texels, snap->sh));
    renderer_.prepare(env);
    for (auto& o : objects_) o.environment = env;
    light_version_ = snap->version;
  }
  for (int c = 0; c < 3; ++c) work.camera.exposure[c] = snap->colour_exposure[c];
  work.virtual_view.output = render::ColourOutput::LinearFloat;
  renderer_.render({intrinsics_, work.T_world_camera}, objects_, work.virtual_view);
}

void UploadStage::process(FrameWork& work) {
  auto& q = ctx_.queue();
  // Non-blocking writes: the host images live until the frame is done (download waits).
  work.color.upload(q, work.input->color, false);
  work.real_depth.upload(q, work.input->depth, false);
  if (work.hdr)
    work.virtual_radiance.upload(q, work.virtual_view.radiance, false);
  else
    work.virtual_color.upload(q, work.virtual_view.color, false);
  work.virtual_depth.upload(q, work.virtual_view.depth_mm, false);
  if (!work.alpha.same_size(work.color)) {
    work.alpha.resize(ctx_.context(), work.color.width(), work.color.height());
    work.composite.resize(ctx_.context(), work.color.width(), work.color.height());
  }
}

void OcclusionStage::process(FrameWork& work) {
  method_->process({&work.color, &work.real_depth, &work.virtual_depth}, work.alpha);
}

void CompositeStage::process(FrameWork& work) {
  if (work.hdr)
    hdr_.process(work.color, work.virtual_radiance, work.alpha, work.camera, work.composite);
  else
    composite_.process(work.color, work.virtual_color, work.alpha, work.composite);
}

void DownloadStage::process(FrameWork& work) {
  auto& q = ctx_.queue();
  // Fresh images per frame: the outputs hold them through shared_ptr while the next frame
  // is processed (two 640x480 allocations per frame, measured negligible next to the work).
  auto composite = std::make_shared<ImageRGB8>(work.composite.width(), work.composite.height());
  work.composite.download(q, *composite);
  work.composite_host = std::move(composite);
  if (work.want_alpha) {
    auto alpha = std::make_shared<ImageF>(work.alpha.width(), work.alpha.height());
    work.alpha.download(q, *alpha);
    work.alpha_host = std::move(alpha);
  } else {
    work.alpha_host.reset();
  }
}

}  // namespace probeless

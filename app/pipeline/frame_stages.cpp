#include "app/pipeline/frame_stages.hpp"

namespace probeless {

RenderStage::RenderStage(std::vector<render::VirtualObject> objects, PinholeIntrinsics intrinsics)
    : objects_(std::move(objects)), intrinsics_(intrinsics) {}

void RenderStage::process(FrameWork& work) {
  renderer_.render({intrinsics_, work.T_world_camera}, objects_, work.virtual_view);
}

void UploadStage::process(FrameWork& work) {
  auto& q = ctx_.queue();
  // Non-blocking writes: the host images live until the frame is done (download waits).
  work.color.upload(q, work.input->color, false);
  work.real_depth.upload(q, work.input->depth, false);
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

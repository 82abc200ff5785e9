// The service's stages after the render, given the objects' rectangle (DeviceFrame::objects:
// docs/architecture.md "Only the objects' pixels, end to end"), make the matte and the
// composite of the whole frame, bit for bit, frame after frame along the sim's orbit, with the
// shipped occlusion (CVF with its hole cores, then the stabiliser, which carries its history
// from frame to frame) and the foreground estimate. What a rectangle that jumps leaves behind
// (stale rows, histories) is the stage tests' business (tests/kernels/cvf_local/
// object_rect_test.cpp and the *OverTheObjects* tests), which start from a frame that covered
// everything: this slow orbit does not read such rows.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>

#include "app/pipeline/frame_processor.hpp"
#include "app/pipeline/frame_stages.hpp"
#include "app/pipeline/scene_objects.hpp"
#include "drivers/rig_factory.hpp"
#include "kernels/occlusion/method_registry.hpp"
#include "support/cl_context.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

TEST(ObjectRectChain, TheStagesGiveTheWholeFramesMatteAndComposite) {
  Rig rig = open_rig("sim:realtime=0,trajectory=orbit,frames=8");
  ServiceConfig config;
  place_objects(config.objects, rig.scene);
  ASSERT_EQ(config.occlusion_method, "cvf");
  auto& ctx = testing::cl_context();
  const PinholeIntrinsics k = rig.calibration.rgb.intrinsics();
  RenderStage render(make_scene_objects(config.objects, config.ground), k);
  UploadStage upload(ctx, rig.calibration.rgb, beyond_range_rule(config));
  const auto method = [&] {
    return occlusion::make_method(ctx, config.occlusion_method, occlusion_params(config));
  };
  OcclusionStage whole_matte(ctx, method(), true, k), cut_matte(ctx, method(), true, k);
  CompositeStage whole_composite(ctx), cut_composite(ctx);
  int frames = 0, partial = 0;
  RgbdFrame frame;
  while (frames < 6 && rig.rgbd->read(frame, 5s) == ReadResult::Frame) {
    ASSERT_TRUE(frame.truth && frame.truth->rig_pose);
    const Pose T_world_camera = *frame.truth->rig_pose * rig.calibration.T_rig_rgb;
    const VirtualLayer layer = render.process(T_world_camera);
    ASSERT_TRUE(layer.drawn);
    partial += !layer.drawn->empty() &&
               *layer.drawn != PixelRect::whole(frame.colour.width(), frame.colour.height());
    DeviceFrame device = upload.process(frame, layer);
    const DeviceImageF& cut_matte_device = cut_matte.process(device, T_world_camera);
    const ImageRGB8 cut = cut_composite.process(device, cut_matte_device).download(ctx.queue());
    const ImageF cut_alpha = cut_matte_device.download(ctx.queue());
    device.objects.reset();  // the whole frame, as before the rectangle
    const DeviceImageF& whole_matte_device = whole_matte.process(device, T_world_camera);
    const ImageRGB8 whole =
        whole_composite.process(device, whole_matte_device).download(ctx.queue());
    const ImageF whole_alpha = whole_matte_device.download(ctx.queue());
    EXPECT_EQ(cut_alpha, whole_alpha) << "frame " << frames;
    EXPECT_EQ(cut, whole) << "frame " << frames;
    ++frames;
  }
  EXPECT_EQ(frames, 6);
  EXPECT_GE(partial, 3) << "the objects cover part of the frame, so the rectangle matters";
}

}  // namespace
}  // namespace probeless

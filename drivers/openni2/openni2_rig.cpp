#include "drivers/openni2/openni2_rig.hpp"

#include <cmath>

#include "core/camera/pinhole.hpp"
#include "drivers/openni2/openni2_rgbd_source.hpp"

namespace probeless::openni2 {

Rig open_openni2_rig(std::string_view spec) {
  auto source = std::make_unique<Openni2RgbdSource>(parse_openni2_options(spec));
  PinholeIntrinsics k;
  const CameraInfo* info = source->camera_info();
  k.width = info ? info->colour.width : 640;
  k.height = info ? info->colour.height : 480;
  // Kinect-class default, scaled to the frame size.
  k.fx = k.fy = 525.0 * k.width / 640.0;
  if (info && info->colour_hfov_rad > 0.1f && info->colour_vfov_rad > 0.1f) {
    k.fx = 0.5 * k.width / std::tan(0.5 * info->colour_hfov_rad);
    k.fy = 0.5 * k.height / std::tan(0.5 * info->colour_vfov_rad);
  }
  k.cx = 0.5 * k.width - 0.5;
  k.cy = 0.5 * k.height - 0.5;
  Rig rig;
  rig.calibration.rgb = PinholeCamera(k);
  rig.calibration.fisheye = nullptr;
  rig.calibration.T_rig_rgb = Pose::identity();
  rig.calibration.T_rig_fisheye = Pose::identity();
  rig.rgbd = std::move(source);
  return rig;
}

}  // namespace probeless::openni2

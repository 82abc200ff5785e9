#include "kernels/envmap/envmap_update.hpp"

#include <stdexcept>

#include "kernels/envmap/envmap_update_cl.hpp"

namespace probeless::envmap {

EnvmapUpdate::EnvmapUpdate(ComputeContext& ctx, const UpdateParams& params)
    : ctx_(ctx),
      params_(params),
      kernel_(ctx.kernel("envmap_update", cl_source::envmap_update, {}, "envmap_update")) {}

void EnvmapUpdate::update(const DeviceImage<float, 4>& image, const FisheyeView& view, bool publish,
                          DeviceImage<float, 4>& texels, DeviceImage<float, 4>& pending) {
  const int n = texels.width();
  if (texels.height() != 6 * n) throw std::invalid_argument("EnvmapUpdate: texels must be n x 6n");
  if (!pending.same_size(texels))
    throw std::invalid_argument("EnvmapUpdate: pending must match texels");
  if (texels.empty() || image.empty()) return;
  const Eigen::Matrix3f r = view.R_camera_world.cast<float>();
  const auto row = [&](int i) { return cl_float4{{r(i, 0), r(i, 1), r(i, 2), 0.0F}}; };
  const KannalaBrandtParams& c = view.camera;
  const cl_float4 focal{{static_cast<float>(c.fx), static_cast<float>(c.fy),
                         static_cast<float>(c.cx), static_cast<float>(c.cy)}};
  const cl_float4 k{{static_cast<float>(c.k[0]), static_cast<float>(c.k[1]),
                     static_cast<float>(c.k[2]), static_cast<float>(c.k[3])}};
  const float sigma2 = params_.measurement_sigma * params_.measurement_sigma;
  const float process2 = params_.process_sigma * params_.process_sigma;
  const float change2 =
      params_.change_sigma > 0 ? params_.change_sigma * params_.change_sigma : 0.0F;
  int a = 0;
  kernel_.setArg(a++, texels.buffer());
  kernel_.setArg(a++, pending.buffer());
  kernel_.setArg(a++, image.buffer());
  kernel_.setArg(a++, image.width());
  kernel_.setArg(a++, image.height());
  kernel_.setArg(a++, n);
  kernel_.setArg(a++, row(0));
  kernel_.setArg(a++, row(1));
  kernel_.setArg(a++, row(2));
  kernel_.setArg(a++, focal);
  kernel_.setArg(a++, k);
  kernel_.setArg(a++, static_cast<float>(c.max_theta));
  kernel_.setArg(a++, params_.rule == UpdateRule::Kalman ? 0 : 1);
  kernel_.setArg(a++, publish ? 1 : 0);
  kernel_.setArg(a++, sigma2);
  kernel_.setArg(a++, process2);
  kernel_.setArg(a++, change2);
  ctx_.run_2d(kernel_, n, 6 * n);
}

}  // namespace probeless::envmap

#include "kernels/envmap/envmap_downsample.hpp"

#include <stdexcept>

#include "kernels/envmap/envmap_downsample_cl.hpp"

namespace probeless::envmap {

namespace {
int factor_of(int n, int m) {
  if (m < 1 || n % m != 0)
    throw std::invalid_argument("EnvmapDownsample: the face size must divide the keyframe's");
  return n / m;
}
}  // namespace

EnvmapDownsample::EnvmapDownsample(ComputeContext& ctx)
    : ctx_(ctx),
      kernel_(
          ctx.kernel("envmap_downsample", cl_source::envmap_downsample, {}, "envmap_downsample")) {}

void EnvmapDownsample::run(const DeviceImage<float, 4>& texels, int face_size,
                           DeviceImage<float, 4>& out) {
  const int n = texels.width();
  const int factor = factor_of(n, face_size);
  out.resize(ctx_.context(), face_size, 6 * face_size);
  kernel_.setArg(0, texels.buffer());
  kernel_.setArg(1, n);
  kernel_.setArg(2, out.buffer());
  kernel_.setArg(3, face_size);
  kernel_.setArg(4, factor);
  ctx_.run_2d(kernel_, face_size, 6 * face_size);
}

// The reference (a plain loop; same summation order as the kernel).
ImageRGBAF envmap_downsample_reference(const ImageRGBAF& texels, int face_size) {
  const int n = texels.width(), m = face_size;
  const int factor = factor_of(n, m);
  ImageRGBAF out = make_texels(m);
  for (int row = 0; row < 6 * m; ++row) {
    const int face = row / m, y = row - face * m;
    for (int x = 0; x < m; ++x) {
      float sum[3] = {0, 0, 0};
      for (int j = 0; j < factor; ++j)
        for (int i = 0; i < factor; ++i)
          for (int c = 0; c < 3; ++c)
            sum[c] += texels.at(x * factor + i, face * n + y * factor + j, c);
      for (int c = 0; c < 3; ++c) out.at(x, row, c) = sum[c] / static_cast<float>(factor * factor);
      out.at(x, row, 3) = 1.0F;
    }
  }
  return out;
}

}  // namespace probeless::envmap

#pragma once
// An image that lives on the OpenCL device: a buffer laid out exactly like core's Image<T,C>
// (row-major, interleaved, no padding), so stages hand images to each other on the device and
// only the pipeline's ends copy to or from the host.
#include <CL/opencl.hpp>
#include <cstddef>
#include <stdexcept>

#include "core/image.hpp"
#include "kernels/runtime/compute_context.hpp"

namespace probeless {

template <typename T, int Channels>
class DeviceImage {
 public:
  using value_type = T;
  static constexpr int channels = Channels;
  using HostImage = Image<T, Channels>;

  DeviceImage() = default;
  // Uninitialised contents. A 0-sized image holds no buffer (OpenCL has no empty buffers).
  DeviceImage(const ::cl::Context& context, int width, int height,
              cl_mem_flags flags = CL_MEM_READ_WRITE)
      : width_(width), height_(height) {
    if (width < 0 || height < 0) throw std::invalid_argument("DeviceImage: negative size");
    if (size_bytes() > 0) buffer_ = ::cl::Buffer(context, flags, size_bytes());
  }
  DeviceImage(ComputeContext& ctx, int width, int height)
      : DeviceImage(ctx.context(), width, height) {}
  // A device copy of `host` (blocking upload on the context's queue).
  DeviceImage(ComputeContext& ctx, const HostImage& host)
      : DeviceImage(ctx.context(), host.width(), host.height()) {
    upload(ctx.queue(), host);
  }

  // A read-only device image over `host`'s own memory (CL_MEM_USE_HOST_PTR): on a device that
  // shares the host's memory (PoCL on the CPU, most boards' GPUs) kernels read it in place, so
  // a frame is not copied before a kernel that reads only part of it. `host` must stay alive
  // and unchanged until every command using the image has finished.
  static DeviceImage wrap_host(const ::cl::Context& context, const HostImage& host) {
    DeviceImage image;
    image.width_ = host.width();
    image.height_ = host.height();
    if (!image.empty())
      image.buffer_ = ::cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR,
                                   image.size_bytes(), const_cast<T*>(host.data()));
    return image;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return size_bytes() == 0; }
  std::size_t pixel_count() const { return static_cast<std::size_t>(width_) * height_; }
  std::size_t size_bytes() const { return pixel_count() * Channels * sizeof(T); }
  bool same_size(int width, int height) const { return width_ == width && height_ == height; }
  template <typename U, int D>
  bool same_size(const DeviceImage<U, D>& other) const {
    return same_size(other.width(), other.height());
  }

  const ::cl::Buffer& buffer() const { return buffer_; }

  // Reallocates only when the size changes (contents are then undefined).
  void resize(const ::cl::Context& context, int width, int height) {
    if (!same_size(width, height)) *this = DeviceImage(context, width, height);
  }

  // Copies `host` to the device, resizing to it first. Blocking by default, so `host` may be
  // reused at once; with blocking = false it must outlive the transfer (wait on the queue).
  void upload(::cl::CommandQueue& queue, const HostImage& host, bool blocking = true) {
    if (!same_size(host.width(), host.height()))
      resize(queue.getInfo<CL_QUEUE_CONTEXT>(), host.width(), host.height());
    if (!empty())
      queue.enqueueWriteBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, size_bytes(),
                               host.data());
  }
  // Blocking copy to the host; `host` is resized to match.
  void download(::cl::CommandQueue& queue, HostImage& host) const {
    if (!(host.width() == width_ && host.height() == height_)) host = HostImage(width_, height_);
    if (!empty()) queue.enqueueReadBuffer(buffer_, CL_TRUE, 0, size_bytes(), host.data());
  }
  HostImage download(::cl::CommandQueue& queue) const {
    HostImage host(width_, height_);
    download(queue, host);
    return host;
  }

 private:
  ::cl::Buffer buffer_;
  int width_ = 0;
  int height_ = 0;
};

using DeviceImageRGB8 = DeviceImage<std::uint8_t, 3>;
using DeviceImageRGBA8 = DeviceImage<std::uint8_t, 4>;
using DeviceImageGray8 = DeviceImage<std::uint8_t, 1>;
using DeviceDepthImage = DeviceImage<std::uint16_t, 1>;
using DeviceImageF = DeviceImage<float, 1>;

}  // namespace probeless

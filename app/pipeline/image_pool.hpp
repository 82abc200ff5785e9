#pragma once
// Host images for the frames handed to the outputs, reused once every holder has let go.
//
// The download stage used to allocate a fresh composite (and matte) per frame: at 640x480 that
// is 0.9 MB zeroed by the constructor, then faulted in page by page by the device's copy; the
// kernel's page clearing alone was 2.9 % of `bench pipeline`'s CPU samples (docs/performance.md).
// The outputs keep a frame only through its shared_ptr (the output slot, the encoders, the last
// good frame for NO SIGNAL), so an image whose only owner is the pool is free to be written.
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/image.hpp"

namespace probeless {

template <typename T, int C>
class ImagePool {
 public:
  // Keeps at most `capacity` images; beyond that, take() hands out images it does not keep.
  explicit ImagePool(std::size_t capacity) : capacity_(capacity) {}

  // A width x height image nobody else holds, its contents whatever they were (the caller
  // overwrites every pixel). Only the pool's owner thread may call it.
  std::shared_ptr<Image<T, C>> take(int width, int height) {
    for (auto& image : images_) {
      // use_count() == 1: only the pool holds it, and no one can copy it from anyone else. The
      // fence pairs with the release of the last other holder's decrement, so that its reads
      // happen before the writes that follow.
      if (image.use_count() == 1 && image->width() == width && image->height() == height) {
        std::atomic_thread_fence(std::memory_order_acquire);
        return image;
      }
    }
    auto fresh = std::make_shared<Image<T, C>>(width, height);
    if (images_.size() < capacity_) {
      images_.push_back(fresh);
    } else {
      // Full: replace an idle image of another size (the frame size changed), if any.
      for (auto& image : images_)
        if (image.use_count() == 1) {
          image = fresh;
          break;
        }
    }
    return fresh;
  }

  std::size_t size() const { return images_.size(); }

 private:
  std::size_t capacity_;
  std::vector<std::shared_ptr<Image<T, C>>> images_;
};

}  // namespace probeless

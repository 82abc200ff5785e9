#pragma once
// Plain C++ of push_pull.cl and PushPull::fill, for the kernel tests.
#include "kernels/envmap/envmap_types.hpp"

namespace probeless::envmap {

// Fills texels (n x 6n) in place; returns the mask of faces that had observed texels.
int push_pull_reference(ImageRGBAF& texels);

}  // namespace probeless::envmap

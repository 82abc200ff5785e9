#pragma once
// A tiny TUM RGB-D sequence on disk (tum_test.cpp writes it), shared by the TUM reader's tests
// and the record command's.
#include <filesystem>
#include <vector>

#include "core/image.hpp"

namespace probeless::replay {

struct TumFixture {
  std::filesystem::path dir;
  std::vector<DepthImage> depth;
  std::vector<ImageRGB8> colour;
};

// 4 colour and 4 depth images whose timestamps interleave as in freiburg1; 3 pairs associate.
TumFixture make_tum_sequence(bool with_groundtruth = true);

}  // namespace probeless::replay

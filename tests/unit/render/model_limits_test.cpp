// Hostile model files (core/read_limits.hpp): counts and offsets that would wrap size_t
// arithmetic or claim more than the file holds are refused, naming the accessor, before
// anything is allocated for them.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/render/mesh.hpp"
#include "support/memory_cap.hpp"
#include "support/test_data.hpp"

namespace probeless::render {
namespace {

namespace fs = std::filesystem;

// One triangle's worth of JSON whose POSITION accessor (0) has the given count and byte
// offset, over a 12-byte buffer (one vertex) in "one.bin" beside it.
fs::path gltf_claiming(const std::string& name, const std::string& count,
                       const std::string& byte_offset = "0") {
  const fs::path dir = testing::scratch_dir();
  const float vertex[3] = {0, 0, 0};
  std::ofstream(dir / "one.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(vertex), sizeof vertex);
  std::ofstream(dir / name) << R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "buffers":[{"byteLength":12,"uri":"one.bin"}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":12}],
    "accessors":[{"bufferView":0,"byteOffset":)"
                            << byte_offset << R"(,"componentType":5126,"count":)" << count
                            << R"(,"type":"VEC3"}]})";
  return dir / name;
}

std::string load_capped(const fs::path& path) {
  return testing::what_with_memory_cap(64u << 20, [&] { (void)load_gltf(path); });
}

// The issue's file: count * 12 wraps to 8 (mod 2^64), so the bounds check passed and the
// loader read far past the buffer (SIGSEGV).
TEST(ModelLimits, GltfCountThatWrapsIsRefused) {
  const std::string what = load_capped(gltf_claiming("wrap.gltf", "6148914691236517206"));
  EXPECT_NE(what.find("POSITION (accessor 0): count 6148914691236517206 is over the limit"),
            std::string::npos)
      << what;
}

// count 2^27 took the process to 3.4 GB before the bounds check refused it; a count within
// the limit is refused by the bounds check, before the values are allocated.
TEST(ModelLimits, GltfCountBeyondTheBufferIsRefusedBeforeAllocation) {
  std::string what = load_capped(gltf_claiming("big.gltf", "134217728"));
  EXPECT_NE(what.find("count 134217728 is over the limit of 16777216"), std::string::npos) << what;
  what = load_capped(gltf_claiming("past.gltf", "16777216"));
  EXPECT_NE(what.find("POSITION (accessor 0): 16777216 elements at byte 0 read past the end"),
            std::string::npos)
      << what;
}

// A byte offset near 2^64 wrapped the sum of offsets the same way.
TEST(ModelLimits, GltfByteOffsetThatWrapsIsRefused) {
  const std::string what = load_capped(gltf_claiming("offset.gltf", "1", "18446744073709551604"));
  EXPECT_NE(what.find("read past the end of its buffer view"), std::string::npos) << what;
}

// Model files over the size limit are refused before a parser reads them (a sparse file: no
// disk space is used).
TEST(ModelLimits, FilesOverTheSizeLimitAreRefusedUnread) {
  const fs::path dir = testing::scratch_dir();
  for (const char* name : {"huge.obj", "huge.gltf"}) {
    std::ofstream(dir / name).put('#');
    fs::resize_file(dir / name, (std::uintmax_t{1} << 30) + 1);
    const std::string what =
        testing::what_with_memory_cap(64u << 20, [&] { (void)load_model(dir / name); });
    EXPECT_NE(what.find("1073741825 bytes, over the limit of 1073741824"), std::string::npos)
        << what;
  }
}

}  // namespace
}  // namespace probeless::render

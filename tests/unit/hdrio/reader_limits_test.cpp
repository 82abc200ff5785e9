// Hostile headers (core/read_limits.hpp): each reader refuses what a tiny file claims, with a
// clear error, before it allocates for it (the readers run with 64 MiB to spare).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>

#include "drivers/io/hdr_image.hpp"
#include "drivers/io/pfm.hpp"
#include "support/memory_cap.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

constexpr std::size_t kHeadroom = 64u << 20;

std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
  const auto path = testing::scratch_dir() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string read_hdr_capped(const std::filesystem::path& path) {
  return testing::what_with_memory_cap(kHeadroom, [&] { (void)read_hdr_image(path); });
}

// The file: 52 bytes that claimed 16384 x 16384 pixels took eval sh --probe to 3.2 GB.
TEST(ReaderLimits, RadianceHeaderWithoutPixels) {
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 16384\n";
  EXPECT_NE(read_hdr_capped(write_file("huge.hdr", header)).find("bad image size 16384x16384"),
            std::string::npos);
  // Within the pixel limit, but 8192 scanlines cannot fit in no bytes.
  const std::string what =
      read_hdr_capped(write_file("empty.hdr", "#?RADIANCE\n\n-Y 8192 +X 8192\n"));
  EXPECT_NE(what.find("empty.hdr: truncated: 8192 scanlines need at least 32768 bytes, 0 left"),
            std::string::npos)
      << what;
}

// EXPOSURE lines multiply; a product of 0 (underflow) gave infinite radiance.
TEST(ReaderLimits, RadianceExposureOutOfRange) {
  const std::string pixel = std::string("\x80\x80\x80\x81", 4);
  for (const char* exposure :
       {"EXPOSURE=1e-200\nEXPOSURE=1e-200", "EXPOSURE=1e-39", "EXPOSURE=1e300\nEXPOSURE=1e300"}) {
    const std::string file = std::string("#?RADIANCE\n") + exposure + "\n\n-Y 1 +X 1\n" + pixel;
    const std::string what = read_hdr_capped(write_file("exposure.hdr", file));
    EXPECT_NE(what.find("EXPOSURE values multiply to"), std::string::npos)
        << exposure << ": " << what;
  }
  // An ordinary one still reads.
  const std::string ok = "#?RADIANCE\nEXPOSURE=1e-30\n\n-Y 1 +X 1\n" + pixel;
  EXPECT_EQ(read_hdr_capped(write_file("exposure_ok.hdr", ok)), "");
}

// 20 bytes claimed 32768 x 32768 floats (4 GiB).
TEST(ReaderLimits, PfmHeaderWithoutData) {
  auto read_capped = [](const std::filesystem::path& path) {
    return testing::what_with_memory_cap(kHeadroom, [&] { (void)read_pfm(path); });
  };
  std::string what = read_capped(write_file("huge.pfm", "Pf\n32768 32768\n-1\n"));
  EXPECT_NE(what.find("bad PFM size 32768x32768"), std::string::npos) << what;
  what = read_capped(write_file("short.pfm", "Pf\n8192 8192\n-1\nabcd"));
  EXPECT_NE(what.find("truncated PFM data (4 of 268435456 bytes)"), std::string::npos) << what;
  EXPECT_EQ(read_capped(write_file("one.pfm", std::string("Pf\n1 1\n-1\n\0\0\x80?", 15))), "");
}

// The header of a small valid EXR with its data window widened to 8192 x 8192 (within the
// limits), an empty offset table and no chunk. Refused before the pixels (768 MiB) are
// allocated.
TEST(ReaderLimits, OpenExrHeaderWithoutChunks) {
  const auto good = testing::scratch_dir() / "small.exr";
  write_hdr_image(good, ImageRGBF(4, 4, 0.5f));
  std::string bytes(std::filesystem::file_size(good), '\0');
  std::ifstream(good, std::ios::binary)
      .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  // Attributes after the 8-byte magic and version: name\0 type\0 size value, then a \0.
  std::size_t at = 8, window = std::string::npos;
  while (at < bytes.size() && bytes[at] != '\0') {
    const std::size_t type = bytes.find('\0', at) + 1;
    const std::size_t size_at = bytes.find('\0', type) + 1;
    std::int32_t size = 0;
    std::memcpy(&size, &bytes[size_at], 4);
    if (bytes.compare(at, 11, std::string("dataWindow\0", 11)) == 0) window = size_at + 4;
    at = size_at + 4 + static_cast<std::size_t>(size);
  }
  ASSERT_NE(window, std::string::npos);
  const std::int32_t box[4] = {0, 0, 8191, 8191};  // xmin ymin xmax ymax, little-endian
  std::memcpy(&bytes[window], box, sizeof box);
  // The header, then an offset table of zeros for 8192 lines in ZIP chunks of 16 (what the
  // writer uses), and no chunk.
  bytes.resize(at + 1 + 8192 / 16 * 8, '\0');
  const std::string what = read_hdr_capped(write_file("wide.exr", bytes));
  EXPECT_NE(what.find("wide.exr: truncated"), std::string::npos) << what;
  EXPECT_EQ(read_hdr_capped(good), "");
}

// Found by the exr fuzz target: OpenEXR allocated a header attribute at the size the file
// claims (1.6 GB from 297 bytes) before reading it. A comment attribute claiming 1.5 GB in a
// file of a few hundred bytes is refused before OpenEXR sees the file.
TEST(ReaderLimits, OpenExrAttributeLargerThanTheFile) {
  const auto good = testing::scratch_dir() / "small_for_attribute.exr";
  write_hdr_image(good, ImageRGBF(2, 2, 0.5f));
  std::string bytes(std::filesystem::file_size(good), '\0');
  std::ifstream(good, std::ios::binary)
      .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  // A first attribute after the 8-byte magic and version: name, type, size, no value.
  const std::int32_t claimed = 1'500'000'000;
  std::string attribute("comments\0string\0", 16);
  attribute.append(reinterpret_cast<const char*>(&claimed), 4);  // little-endian host
  bytes.insert(8, attribute);
  // Refused as a bad header (OpenEXR's core, strict) before the C++ reader allocates it.
  const std::string what = read_hdr_capped(write_file("attribute.exr", bytes));
  EXPECT_NE(what.find("attribute.exr: OpenEXR: bad header"), std::string::npos) << what;
  // A negative size is refused the same way; the file itself still reads.
  const std::int32_t negative = -5;
  bytes.replace(8 + 16, 4, reinterpret_cast<const char*>(&negative), 4);
  const std::string what_negative = read_hdr_capped(write_file("negative.exr", bytes));
  EXPECT_NE(what_negative.find("negative.exr: OpenEXR: bad header"), std::string::npos)
      << what_negative;
  EXPECT_EQ(read_hdr_capped(good), "");
}

// The fuzz target's inputs themselves (tests/fuzz/corpus/exr/crash-*): a 297-byte file whose
// header made OpenEXR allocate 1.6 GB, and one whose channel list, read by OpenEXR past its
// declared size, put a 1.9 GB opaque attribute where a size walk saw none, and one whose
// displayWindow of 24 bytes (a box2i is 16) did the same with 1 GB past a lenient header check.
TEST(ReaderLimits, OpenExrFuzzFindingsAreRefusedBeforeAllocating) {
  const std::filesystem::path corpus =
      std::filesystem::path(PROBELESS_TEST_SOURCE_DIR) / "../../fuzz/corpus/exr";
  for (const char* name : {"crash-opaque-attribute-1.6GB.exr", "crash-chlist-then-opaque-1.9GB.exr",
                           "crash-display-window-size-1GB.exr"}) {
    const std::string what = read_hdr_capped(corpus / name);
    EXPECT_NE(what.find(std::string(name) + ": OpenEXR: bad header"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace probeless

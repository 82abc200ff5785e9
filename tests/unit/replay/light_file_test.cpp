// The ground-truth light cubemap file (drivers/replay/light_file.hpp): a round trip, and
// hostile headers refused before anything is allocated for them (findings of tests/fuzz).
#include "drivers/replay/light_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "drivers/io/png.hpp"
#include "support/memory_cap.hpp"
#include "support/test_data.hpp"

namespace probeless::replay {
namespace {

std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
  const auto path = testing::scratch_dir() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(LightFile, RoundTrip) {
  Cubemap cube(2);
  float v = 0;
  for (auto& face : cube.faces)
    for (auto& e : face.elements()) e = v++;
  const auto path = testing::scratch_dir() / "light_round_trip.pfm";
  write_light_cubemap(path, cube);
  const Cubemap back = read_light_cubemap(path);
  for (std::size_t f = 0; f < 6; ++f)
    EXPECT_TRUE(std::ranges::equal(back.faces[f].elements(), cube.faces[f].elements()))
        << "face " << f;
}

// Found by the light_cubemap fuzz target: a 20-byte header claiming six 4096 x 4096 faces
// made the reader allocate 1.2 GB before it found the data missing.
TEST(LightFile, HeaderWithoutDataIsRefusedBeforeAllocating) {
  const auto path = write_file("light_huge.pfm", "PF\n4096 24576\n-1.0\n");
  const std::string what =
      testing::what_with_memory_cap(std::size_t{64} << 20, [&] { (void)read_light_cubemap(path); });
  EXPECT_NE(what.find("truncated PFM (0 of 1207959552 bytes of image data)"), std::string::npos)
      << what;
  // One float short of two 2 x 2 faces... of six: also refused, naming the sizes.
  const std::string short_data(6 * 2 * 2 * 3 * 4 - 4, '\0');
  const std::string what_short = testing::what_with_memory_cap(std::size_t{64} << 20, [&] {
    (void)read_light_cubemap(write_file("light_short.pfm", "PF\n2 12\n-1.0\n" + short_data));
  });
  EXPECT_NE(what_short.find("truncated PFM (284 of 288 bytes"), std::string::npos) << what_short;
}

}  // namespace
}  // namespace probeless::replay

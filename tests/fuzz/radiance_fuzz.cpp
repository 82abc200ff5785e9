// Radiance RGBE (drivers/io/hdr_image.hpp, hdr_radiance.cpp) through read_hdr_image on a .hdr
// file, the light probes' way in.
#include "drivers/io/hdr_image.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_scratch("input.hdr", fuzz::as_text(data, size));
  fuzz::expect_accept_or_refuse([&] { read_hdr_image(path); });
  return 0;
}

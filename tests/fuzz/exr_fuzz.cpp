// OpenEXR (drivers/io/hdr_image.hpp) through read_hdr_image on a .exr file.
#include "drivers/io/hdr_image.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_scratch("input.exr", fuzz::as_text(data, size));
  fuzz::expect_accept_or_refuse([&] { read_hdr_image(path); });
  return 0;
}

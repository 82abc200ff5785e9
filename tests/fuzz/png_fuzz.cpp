// PNG (drivers/io/png.hpp): every reader on the same file; each converts or refuses.
#include "drivers/io/png.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_scratch("input.png", fuzz::as_text(data, size));
  fuzz::expect_accept_or_refuse([&] { read_png_rgb8(path); });
  fuzz::expect_accept_or_refuse([&] { read_png_gray8(path); });
  fuzz::expect_accept_or_refuse([&] { read_png_depth16(path); });
  fuzz::expect_accept_or_refuse([&] { read_png_rgb16(path); });
  return 0;
}

// A recording's ground-truth light cubemap (drivers/replay/light_file.hpp: a colour PFM with
// six faces stacked).
#include "drivers/replay/light_file.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_scratch("light.pfm", fuzz::as_text(data, size));
  fuzz::expect_accept_or_refuse([&] { replay::read_light_cubemap(path); });
  return 0;
}

// Gray PFM (drivers/io/pfm.hpp, the Middlebury disparities).
#include "drivers/io/pfm.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_scratch("input.pfm", fuzz::as_text(data, size));
  fuzz::expect_accept_or_refuse([&] { read_pfm(path); });
  return 0;
}

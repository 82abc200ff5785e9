// Rig calibration (core/calibration.hpp) as text, and as a file with the OCamCalib fisheye
// file it may name (drivers/replay/calibration_file.hpp: `[fisheye] file = "ocam.txt"`, the
// input's second part).
#include "core/calibration.hpp"
#include "drivers/replay/calibration_file.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  const auto parts = fuzz::split_parts(text, 2);
  fuzz::expect_accept_or_refuse([&] {
    const RigCalibration calibration = parse_rig_calibration(parts[0]);
    // What was accepted writes back and reads again (the recorder does this).
    parse_rig_calibration(to_toml(calibration), "round trip");
  });
  fuzz::write_parts(text, {"calibration.toml", "ocam.txt"});
  fuzz::expect_accept_or_refuse(
      [&] { replay::load_rig_calibration(fuzz::scratch_dir() / "calibration.toml"); });
  return 0;
}

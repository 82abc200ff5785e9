// A recording directory (drivers/replay/recording.hpp) through Recording::open: the input's
// parts are manifest.toml, calibration.toml, rgbd.csv, fisheye.csv, groundtruth.txt and
// fisheye_groundtruth.txt (a missing part: no such file). The image files the seeds name
// (c0.png, d0.png, f0.png, t0.png, l0.pfm) exist, empty: open() checks they exist, no more.
#include "drivers/replay/recording.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace files = replay::files;
  static const bool images = [] {
    for (const char* name : {"c0.png", "d0.png", "f0.png", "t0.png", "l0.pfm"})
      fuzz::write_scratch(name, "");
    return true;
  }();
  (void)images;
  fuzz::write_parts(fuzz::as_text(data, size),
                    {files::kManifest, files::kCalibration, files::kRgbdIndex, files::kFisheyeIndex,
                     files::kRgbdTrajectory, files::kFisheyeTrajectory});
  fuzz::expect_accept_or_refuse([] {
    const auto recording = replay::Recording::open(fuzz::scratch_dir());
    recording->start_ns();
    recording->loop_span_ns();
  });
  return 0;
}

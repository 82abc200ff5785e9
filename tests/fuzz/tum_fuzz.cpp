// A TUM RGB-D sequence (drivers/replay/tum_source.hpp) through open_tum_sequence: the input's
// parts are rgb.txt, depth.txt and groundtruth.txt. The image files the seeds name
// (rgb/1.png, depth/1.png, ...) exist, empty: the lists are checked, the images are not read.
#include "drivers/replay/tum_source.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool images = [] {
    for (const char* dir : {"rgb", "depth"}) {
      std::filesystem::create_directories(fuzz::scratch_dir() / dir);
      for (const char* name : {"1.png", "2.png", "3.png"})
        fuzz::write_scratch(std::string(dir) + "/" + name, "");
    }
    return true;
  }();
  (void)images;
  fuzz::write_parts(fuzz::as_text(data, size), {"rgb.txt", "depth.txt", "groundtruth.txt"});
  fuzz::expect_accept_or_refuse([] { replay::open_tum_sequence(fuzz::scratch_dir()); });
  return 0;
}

// The service config and the board file it names (app/pipeline/service_config.hpp,
// board_file.hpp): the text through parse_service_config, then the same text as a file
// through load_service_config, whose `board = "board.toml"` picks up the input's second part.
#include <cstdlib>

#include "app/pipeline/service_config.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool hermetic = [] {  // board names resolve in the scratch directory only
    setenv("PROBELESS_BOARD_DIR", fuzz::scratch_dir().c_str(), 1);
    return true;
  }();
  (void)hermetic;
  const std::string_view text = fuzz::as_text(data, size);
  const auto parts = fuzz::split_parts(text, 2);
  fuzz::expect_accept_or_refuse([&] { parse_service_config(parts[0]); });
  fuzz::write_parts(text, {"config.toml", "board.toml"});
  fuzz::expect_accept_or_refuse(
      [&] { load_service_config((fuzz::scratch_dir() / "config.toml").string()); });
  return 0;
}

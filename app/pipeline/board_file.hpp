#pragma once
// Board files (docs/boards.md): a board's sensors, pins, OpenCL device and display as a
// service config (board/<name>/board.toml, installed under /usr/share/probeless/board/),
// which a config file names with `board = "..."` (or `--board`) and overrides key by key.
#include <toml++/toml.h>

#include <filesystem>
#include <string>

namespace probeless {

// Where boards are looked up by name: $PROBELESS_BOARD_DIR, else the packaged directory.
std::filesystem::path board_directory();

// The board.toml that `ref` names: a name ("rpi5": board_directory()/rpi5/board.toml), or,
// when it holds a '/' or ends in ".toml", a file or a directory holding board.toml, relative
// to `relative_to`. Throws std::runtime_error saying what was looked for (and, for a name,
// which boards exist).
std::filesystem::path find_board_file(const std::string& ref,
                                      const std::filesystem::path& relative_to);

// Lays `over` onto `base`: tables merge key by key, anything else (values, arrays, arrays
// of tables such as [[object]]) replaces what `base` has. Nodes are moved, so they keep
// their source positions and errors still name the file and line they came from.
void merge_toml(toml::table& base, toml::table&& over);

}  // namespace probeless

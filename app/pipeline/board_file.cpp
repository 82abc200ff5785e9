#include "app/pipeline/board_file.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace probeless {

std::filesystem::path board_directory() {
  const char* env = std::getenv("PROBELESS_BOARD_DIR");
  // Where cmake/Packaging.cmake installs board/ (the .deb's prefix is /usr).
  return env && *env ? std::filesystem::path(env) : "/usr/share/probeless/board";
}

std::filesystem::path find_board_file(const std::string& ref,
                                      const std::filesystem::path& relative_to) {
  namespace fs = std::filesystem;
  if (ref.empty()) throw std::runtime_error("board: empty name");
  const bool is_path = ref.find('/') != std::string::npos || ref.ends_with(".toml");
  if (is_path) {
    fs::path p(ref);
    if (p.is_relative()) p = relative_to / p;
    if (fs::is_directory(p)) p /= "board.toml";
    p = p.lexically_normal();  // errors and relative paths then read "b/board.toml"
    if (!fs::is_regular_file(p))
      throw std::runtime_error("board '" + ref + "': no file " + p.string());
    return p;
  }
  const fs::path dir = board_directory();
  const fs::path p = dir / ref / "board.toml";
  if (fs::is_regular_file(p)) return p;
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (fs::is_regular_file(entry.path() / "board.toml")) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw std::runtime_error("board '" + ref + "': no " + p.string() + " (boards in " + dir.string() +
                           ": " + (known.empty() ? "none" : known) +
                           "; PROBELESS_BOARD_DIR sets the directory)");
}

void merge_toml(toml::table& base, toml::table&& over) {
  for (auto&& [key, node] : over) {
    toml::node* mine = base.get(key);
    if (mine && mine->is_table() && node.is_table())
      merge_toml(*mine->as_table(), std::move(*node.as_table()));
    else
      base.insert_or_assign(key, std::move(node));
  }
}

}  // namespace probeless

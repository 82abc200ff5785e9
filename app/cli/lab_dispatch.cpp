#include "app/cli/lab_dispatch.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string_view>

namespace probeless::cli {

std::optional<std::string> lab_command(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--log-level") {  // the one global option that takes a separate value
      ++i;
      continue;
    }
    if (arg.starts_with("-")) continue;
    if (arg == "eval" || arg == "bench" || arg == "calibrate") return std::string(arg);
    return std::nullopt;  // the first command word is the appliance's own
  }
  return std::nullopt;
}

std::vector<std::filesystem::path> lab_binary_candidates() {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const auto dir = self.parent_path();
  return {dir / "probeless-lab",
          (dir / ".." / "lib" / "probeless" / "probeless-lab").lexically_normal()};
}

std::string exec_lab(char** argv, const std::string& command) {
  std::string tried;
  for (const auto& path : lab_binary_candidates()) {
    ::execv(path.c_str(), argv);  // returns only on failure
    tried += fmt::format("\n  {}: {}", path.string(), std::strerror(errno));
  }
  return fmt::format(
      "'probeless {}' is a command of the lab (the probeless-lab package: apt install "
      "probeless-lab), which "
      "is not installed here; looked for:{}",
      command, tried);
}

}  // namespace probeless::cli

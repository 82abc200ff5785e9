#include "lab/cli/lab_commands.hpp"

#include <cstdlib>
#include <fstream>

namespace probeless::cli {

void write_json_report(const std::string& path, const nlohmann::json& report) {
  std::ofstream out(path);
  out << report.dump(2) << "\n";
  if (!out) throw CommandError("cannot write " + path);
}

std::filesystem::path find_shared_data(const std::filesystem::path& relative,
                                       const std::filesystem::path& probe) {
  const char* env = std::getenv("PROBELESS_DATA");
  for (const char* base : {env, "../shared/data", "../../shared/data"}) {
    if (!base || !*base) continue;
    const auto dir = std::filesystem::path(base) / relative;
    if (std::filesystem::exists(dir / probe)) return dir;
  }
  return {};
}

}  // namespace probeless::cli

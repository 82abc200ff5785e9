#include "lab/cli/lab_commands.hpp"

#include <fstream>

namespace probeless::cli {

void write_json_report(const std::string& path, const nlohmann::json& report) {
  std::ofstream out(path);
  out << report.dump(2) << "\n";
  if (!out) throw CommandError("cannot write " + path);
}

}  // namespace probeless::cli

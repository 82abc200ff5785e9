#include "app/cli/command_line.hpp"

#include <spdlog/spdlog.h>

#include <exception>
#include <string>

#include "app/cli/logging.hpp"

namespace probeless::cli {

int run_command_line(CLI::App& app, int argc, char** argv,
                     const std::function<void(CLI::App&)>& add_commands) {
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  add_commands(app);
  app.parse_complete_callback([&] { setup_logging(log_level.c_str()); });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}

}  // namespace probeless::cli

// probeless: the appliance's command line (the lab's `eval` and `bench` are handed on to
// probeless-lab, lab/cli/main.cpp). Commands register themselves (app/cli/commands.hpp); errors
// become exceptions that are caught here, once, and printed with their context.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "app/cli/commands.hpp"
#include "app/cli/lab_dispatch.hpp"
#include "app/cli/logging.hpp"

int main(int argc, char** argv) {
  if (const auto lab = probeless::cli::lab_command(argc, argv)) {
    const std::string why = probeless::cli::exec_lab(argv, *lab);  // returns only on failure
    spdlog::error("{}", why);
    return 1;
  }
  CLI::App app{"probeless: headless mixed-reality appliance service"};
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  probeless::cli::add_run_command(app);
  probeless::cli::add_record_command(app);
  probeless::cli::add_devices_command(app);
  // Listed for --help; lab_command() hands them to the lab binary before parsing.
  app.add_subcommand("bench", "Benchmarks that print numbers (the lab: probeless-lab)")
      ->allow_extras();
  app.add_subcommand("eval", "Evaluations against ground truth (the lab: probeless-lab)")
      ->allow_extras();
  app.parse_complete_callback([&] { probeless::cli::setup_logging(log_level.c_str()); });
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

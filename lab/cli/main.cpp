// probeless-lab: the lab's command line, `probeless eval ...` and `probeless bench ...`. The
// appliance binary execs this one with its own arguments (app/cli/lab_dispatch.hpp), so the
// program name, flags, output and exit codes are those of `probeless`.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "app/cli/logging.hpp"
#include "lab/cli/lab_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"probeless: headless mixed-reality appliance service (the lab: eval, bench)",
               "probeless"};
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  auto* bench = app.add_subcommand("bench", "Benchmarks that print numbers");
  bench->require_subcommand(1);
  probeless::cli::add_bench_sim_command(*bench);
  probeless::cli::add_bench_pipeline_command(*bench);
  probeless::cli::add_bench_composite_command(*bench);
  probeless::cli::add_bench_occlusion_command(*bench);
  probeless::cli::add_bench_light_command(*bench);
  auto* eval = app.add_subcommand("eval", "Evaluations against ground truth");
  eval->require_subcommand(1);
  probeless::cli::add_eval_occlusion_command(*eval);
  probeless::cli::add_eval_hdr_command(*eval);
  probeless::cli::add_eval_light_command(*eval);
  probeless::cli::add_eval_render_command(*eval);
  probeless::cli::add_eval_sh_command(*eval);

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

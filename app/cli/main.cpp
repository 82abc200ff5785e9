// probeless: the appliance's command line. The lab's `eval`, `bench` and `calibrate` go to
// probeless-lab (lab/cli/main.cpp, app/cli/lab_dispatch.hpp). Commands register themselves
// (app/cli/commands.hpp); errors are caught once, in run_command_line().
#include <spdlog/spdlog.h>

#include "app/cli/command_line.hpp"
#include "app/cli/commands.hpp"
#include "app/cli/lab_dispatch.hpp"
#include "app/service/crash_report.hpp"

int main(int argc, char** argv) {
  probeless::install_crash_report("probeless");
  if (const auto lab = probeless::cli::lab_command(argc, argv)) {
    const std::string why = probeless::cli::exec_lab(argv, *lab);  // returns only on failure
    spdlog::error("{}", why);
    return 1;
  }
  CLI::App app{"probeless: headless mixed-reality appliance service"};
  return probeless::cli::run_command_line(app, argc, argv, [](CLI::App& a) {
    probeless::cli::add_run_command(a);
    probeless::cli::add_record_command(a);
    probeless::cli::add_devices_command(a);
    // Listed for --help; lab_command() hands them to the lab binary before parsing.
    a.add_subcommand("bench", "Benchmarks that print numbers (the lab: probeless-lab)")
        ->allow_extras();
    a.add_subcommand("eval", "Evaluations against ground truth (the lab: probeless-lab)")
        ->allow_extras();
    a.add_subcommand("calibrate",
                     "Camera and rig calibration from board views (the lab: probeless-lab)")
        ->allow_extras();
  });
}

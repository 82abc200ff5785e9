#pragma once
// Each subcommand lives in its own file and registers itself on the parent command it is
// given. main.cpp only lists them, in the order `--help` shows them. The appliance's commands
// are here; the lab's (`eval`, `bench`) are declared in lab/cli/lab_commands.hpp.
#include <CLI/CLI.hpp>

namespace probeless::cli {

// Thrown by a command for a failure the user can act on; main prints the message and exits 1.
struct CommandError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// probeless run [--config FILE] [--source SPEC] [--frames N] [--out DIR] (run_command.cpp)
void add_run_command(CLI::App& app);

// probeless record --source SPEC --frames N [--no-truth] [--force] DIR (record_command.cpp)
void add_record_command(CLI::App& app);

// probeless devices [--config FILE] [--cl-platform S] [--cl-device S] (devices_command.cpp)
void add_devices_command(CLI::App& app);

}  // namespace probeless::cli

#pragma once
// The command-line edge both binaries share (probeless, probeless-lab): the global
// --log-level option, logging set up once parsing is done, and the one place where errors
// become a message and an exit code (STYLE.md: only the CLI edge prints and exits).
#include <CLI/CLI.hpp>
#include <functional>

namespace probeless::cli {

// Adds --log-level and the commands `add_commands` registers on `app`, parses, runs the chosen
// command's callbacks, and returns the process's exit code.
int run_command_line(CLI::App& app, int argc, char** argv,
                     const std::function<void(CLI::App&)>& add_commands);

}  // namespace probeless::cli

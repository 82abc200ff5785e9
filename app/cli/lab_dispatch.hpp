#pragma once
// `probeless eval ...`, `probeless bench ...` and `probeless calibrate ...` live in the lab
// (docs/architecture.md "The lab"), a binary of their own so that the appliance never links the
// evaluators or OpenCV. The appliance's main hands those commands on, as git does with its
// subcommands: same arguments, same exit code, same output.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace probeless::cli {

// "eval", "bench" or "calibrate" when that is the command argv names (after the global options),
// else none.
std::optional<std::string> lab_command(int argc, char** argv);

// Where the lab binary may be, in order: beside this binary (the build tree), then
// ../lib/probeless/ from it (an install: /usr/bin/probeless, /usr/lib/probeless/probeless-lab).
std::vector<std::filesystem::path> lab_binary_candidates();

// Replaces this process with the lab binary given the same arguments. Returns only when no
// candidate could be executed, with the message to print (naming where it looked).
std::string exec_lab(char** argv, const std::string& command);

}  // namespace probeless::cli

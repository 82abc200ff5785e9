#pragma once
namespace probeless::cli {
// Logging to stderr. Under systemd (JOURNAL_STREAM set) each line starts with the sd-daemon
// priority prefix "<N>" and carries no timestamp (journald adds its own); on a terminal lines
// have a time and colour. `level` is an spdlog level name ("info", "debug", ...).
void setup_logging(const char* level);
}  // namespace probeless::cli

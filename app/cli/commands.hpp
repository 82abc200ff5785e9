#pragma once
// Each subcommand lives in its own file and registers itself on the parent command it is
// given. main.cpp only lists them, in the order `--help` shows them.
#include <CLI/CLI.hpp>

namespace probeless::cli {

// Thrown by a command for a failure the user can act on; main prints the message and exits 1.
struct CommandError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// probeless run [--config FILE] [--source SPEC] [--frames N] [--out DIR] (run_command.cpp)
void add_run_command(CLI::App& app);
// probeless bench pipeline [--frames N] [--json FILE] (bench_pipeline_command.cpp)
void add_bench_pipeline_command(CLI::App& bench);

// probeless record --source SPEC --frames N [--no-truth] [--force] DIR (record_command.cpp)
void add_record_command(CLI::App& app);

// probeless devices [--config FILE] [--cl-platform S] [--cl-device S] (devices_command.cpp)
void add_devices_command(CLI::App& app);
// probeless bench composite [--width W --height H --frames N] (bench_composite_command.cpp)
void add_bench_composite_command(CLI::App& bench);
// probeless eval occlusion --dataset KIND:DIR [--json F --plots D] (eval_occlusion_command.cpp)
void add_eval_occlusion_command(CLI::App& eval);
// probeless eval hdr --image F.hdr [--bits 8|12] [--json F] (eval_hdr_command.cpp)
void add_eval_hdr_command(CLI::App& eval);
// probeless eval sh --probe F.hdr [--json F --scale S --convention z-up|y-up] (eval_sh_command.cpp)
void add_eval_sh_command(CLI::App& eval);
// probeless bench occlusion [--json FILE] (bench_occlusion_command.cpp)
void add_bench_occlusion_command(CLI::App& bench);

// probeless bench sim [--frames N --sim OPTS --json FILE] (bench_sim_command.cpp)
void add_bench_sim_command(CLI::App& bench);

// probeless eval light --source sim [--seconds S --json F] (eval_light_command.cpp)
void add_eval_light_command(CLI::App& eval);
void add_eval_render_command(CLI::App& eval);
// probeless bench light [--frames N --json FILE] (bench_light_command.cpp)
void add_bench_light_command(CLI::App& bench);

}  // namespace probeless::cli

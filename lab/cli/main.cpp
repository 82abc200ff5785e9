// probeless-lab: the lab's command line, `probeless eval ...` and `probeless bench ...`. The
// appliance binary execs this one with its own arguments (app/cli/lab_dispatch.hpp), so the
// program name, flags, output and exit codes are those of `probeless`.
#include "app/cli/command_line.hpp"
#include "lab/cli/lab_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"probeless: headless mixed-reality appliance service (the lab: eval, bench)",
               "probeless"};
  return probeless::cli::run_command_line(app, argc, argv, [](CLI::App& a) {
    auto* bench = a.add_subcommand("bench", "Benchmarks that print numbers");
    bench->require_subcommand(1);
    probeless::cli::add_bench_sim_command(*bench);
    probeless::cli::add_bench_pipeline_command(*bench);
    probeless::cli::add_bench_composite_command(*bench);
    probeless::cli::add_bench_occlusion_command(*bench);
    probeless::cli::add_bench_light_command(*bench);
    probeless::cli::add_bench_tracking_command(*bench);
    probeless::cli::add_bench_soak_command(*bench);
    probeless::cli::add_bench_http_command(*bench);
    probeless::cli::add_bench_latency_command(*bench);
    auto* eval = a.add_subcommand("eval", "Evaluations against ground truth");
    eval->require_subcommand(1);
    probeless::cli::add_eval_occlusion_command(*eval);
    probeless::cli::add_eval_hdr_command(*eval);
    probeless::cli::add_eval_light_command(*eval);
    probeless::cli::add_eval_render_command(*eval);
    probeless::cli::add_eval_sh_command(*eval);
    probeless::cli::add_eval_marker_command(*eval);
    probeless::cli::add_eval_tracking_command(*eval);
    probeless::cli::add_calibrate_command(a);
  });
}

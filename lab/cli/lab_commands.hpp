#pragma once
// The lab's commands (docs/architecture.md "The lab"): evaluations against ground truth and
// benchmarks. They run as `probeless eval ...` / `probeless bench ...`: the appliance binary
// hands those to the lab binary (app/cli/lab_dispatch.hpp), which registers them here.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli/commands.hpp"

namespace probeless::cli {

// Writes a command's `--json` report (indented, as scripts read it); throws CommandError when
// the file cannot be written.
void write_json_report(const std::string& path, const nlohmann::json& report);

// `relative` under the third-party data (../shared/data/README.md) when `relative / probe`
// exists there: $PROBELESS_DATA, else ../shared/data or ../../shared/data from the working
// directory (a checkout or its build tree). Empty when absent: benches then use a stand-in.
std::filesystem::path find_shared_data(const std::filesystem::path& relative,
                                       const std::filesystem::path& probe);

// probeless bench pipeline [--frames N] [--json FILE] (bench_pipeline_command.cpp)
void add_bench_pipeline_command(CLI::App& bench);
// probeless bench composite [--width W --height H --frames N] (bench_composite_command.cpp)
void add_bench_composite_command(CLI::App& bench);
// probeless bench occlusion [--json FILE] (bench_occlusion_command.cpp)
void add_bench_occlusion_command(CLI::App& bench);
// probeless bench sim [--frames N --sim OPTS --json FILE] (bench_sim_command.cpp)
void add_bench_sim_command(CLI::App& bench);
// probeless bench light [--frames N --json FILE] (bench_light_command.cpp)
void add_bench_light_command(CLI::App& bench);
// probeless bench tracking [--dataset tum:DIR --frames N --json F] (bench_tracking_command.cpp)
void add_bench_tracking_command(CLI::App& bench);
// probeless bench soak [--minutes N --json F] (bench_soak_command.cpp)
void add_bench_soak_command(CLI::App& bench);
// probeless bench http [--json F] (bench_http_command.cpp)
void add_bench_http_command(CLI::App& bench);
// probeless bench latency [--seconds N --json F] (bench_latency_command.cpp)
void add_bench_latency_command(CLI::App& bench);

// probeless eval occlusion --dataset KIND:DIR [--json F --plots D] (eval_occlusion_command.cpp)
void add_eval_occlusion_command(CLI::App& eval);
// probeless eval hdr --image F.hdr [--bits 8|12] [--json F] (eval_hdr_command.cpp)
void add_eval_hdr_command(CLI::App& eval);
// probeless eval sh --probe F.hdr [--json F --scale S --convention z-up|y-up] (eval_sh_command.cpp)
void add_eval_sh_command(CLI::App& eval);
// probeless eval light --source sim [--seconds S --json F] (eval_light_command.cpp)
void add_eval_light_command(CLI::App& eval);
// probeless eval render --source sim [--seconds S --json F] (eval_render_command.cpp)
void add_eval_render_command(CLI::App& eval);
// probeless eval marker --image F --camera F.yml [--board SPEC --json F] (eval_marker_command.cpp)
void add_eval_marker_command(CLI::App& eval);
// probeless eval tracking --dataset tum:DIR|sim [--methods L --frames N --json F]
// (eval_tracking_command.cpp)
void add_eval_tracking_command(CLI::App& eval);

// probeless calibrate --images DIR --board SPEC [--model M --camera-out F --json F] | --import-ocam
// FILE --camera-out F | --recording DIR | --rgb-images D --fisheye-images D ... --out F
// (calibrate_command.cpp)
void add_calibrate_command(CLI::App& app);

}  // namespace probeless::cli

// `probeless run`: the service. With no arguments it runs the synthetic rig with a built-in
// object and serves the composite on http://127.0.0.1:8080/.
#include <spdlog/spdlog.h>

#include <iostream>

#include "app/cli/commands.hpp"
#include "app/pipeline/pipeline.hpp"
#include "app/service/heap_trim.hpp"
#include "app/service/signals.hpp"
#include "app/service/socket_activation.hpp"
#include "app/service/systemd_notifier.hpp"
#include "drivers/rig_factory.hpp"

namespace probeless::cli {
namespace {

struct RunArgs {
  std::string config_path;
  std::string board;
  std::string source;
  std::string out_dir;
  std::string occlusion;
  std::string address;
  std::string allow_origin;  // ustreamer's --allow-origin: [http] cors_origin
  int port = -1;
  std::int64_t frames = 0;
  bool matte = false;
  std::int64_t fault_hang_after = -1;
  std::string fault_hang;  // THREAD:N
};

// "light:40" -> the watchdog tests' fault (PipelineOptions::hang_thread, hang_after_beats).
void parse_fault_hang(const std::string& spec, PipelineOptions& options) {
  const auto colon = spec.find(':');
  const std::string thread = spec.substr(0, colon);
  if (colon == std::string::npos ||
      (thread != "light" && thread != "output" && thread != "http" && thread != "rtsp"))
    throw CommandError("--fault-hang: expected THREAD:N, THREAD one of light, output, http, rtsp");
  options.hang_thread = thread;
  try {
    options.hang_after_beats = std::stoll(spec.substr(colon + 1));
  } catch (const std::exception&) {
    throw CommandError("--fault-hang: N must be an integer");
  }
}

std::string status_line(const nlohmann::json& s) {
  return fmt::format("{} fps {:.1f}, {} frames, rgbd {}", s.value("state", "?"),
                     s.value("fps", 0.0), s["frames"].value("out", 0),
                     s["sources"]["rgbd"].value("state", "?"));
}

void run(const RunArgs& args) {
  ServiceConfig config = load_service_config(args.config_path, args.board);
  if (!args.source.empty()) config.source = args.source;
  if (!args.out_dir.empty()) config.files.dir = args.out_dir;
  if (!args.occlusion.empty()) config.occlusion_method = args.occlusion;
  if (!args.address.empty()) config.http.address = args.address;
  if (args.port >= 0) config.http.port = args.port;
  if (!args.allow_origin.empty()) config.http.access.cors_origin = args.allow_origin;
  if (args.frames > 0) config.max_frames = args.frames;
  if (args.matte) config.files.write_matte = true;
  // Under probeless.socket systemd has bound the port: that socket wins over [http] and
  // --address/--port (docs/appliance.md "Socket activation").
  if (const int fd = http_socket_from_systemd(); fd >= 0) {
    config.http.enabled = true;
    config.http.listen_fd = fd;
    if (auto address = bound_address(fd); !address.empty()) config.http.address = address;
    spdlog::info(
        "HTTP: serving the socket systemd passed (probeless.socket); [http] address "
        "and port are not used");
  }

  ShutdownSignals signals;  // SIGTERM/SIGINT only wake the loop below (app/service/signals.hpp)
  SystemdNotifier notifier;
  PipelineOptions options;
  options.notifier = &notifier;
  options.hang_after_frames = args.fault_hang_after;
  if (!args.fault_hang.empty()) parse_fault_hang(args.fault_hang, options);
  Pipeline pipeline(config, open_rig(config.source), options);
  pipeline.start();
  if (!pipeline.url().empty())
    std::cout << "probeless: serving " << pipeline.url() << "/  (stream: " << pipeline.url()
              << "/stream, status: " << pipeline.url() << "/status)" << std::endl;
  if (!pipeline.rtsp_url().empty())
    std::cout << "probeless: H.264 stream " << pipeline.rtsp_url() << std::endl;
  if (!config.files.dir.empty())
    std::cout << "probeless: writing frames to " << config.files.dir.string() << std::endl;

  // The first frame includes OpenCL program builds (about a second each on PoCL when the
  // binary cache is cold), hence the generous wait.
  bool ready = false;
  HeapTrimmer heap;  // RSS flat over hours (app/service/heap_trim.hpp)
  while (!signals.stop_requested() && !pipeline.finished()) {
    if (!ready && pipeline.wait_first_frame(std::chrono::milliseconds(100))) {
      ready = true;
      notifier.ready();
      spdlog::info("first frame out: ready");
    }
    // systemd arms WatchdogSec= when the process starts, not at READY=1 (the unit was killed
    // 5 s into a start that compiles the OpenCL programs: vm_systemd_unit). The pipeline's
    // ServiceWatchdog beats from the start for the threads already watched; processing and
    // light join at their first frame; TimeoutStartSec bounds the start.
    if (signals.wait_for(std::chrono::milliseconds(ready ? 1000 : 0))) break;
    if (ready) {
      notifier.status(status_line(pipeline.status()));
      heap.maybe_trim();
    }
  }
  notifier.stopping();
  if (signals.stop_requested()) spdlog::info("signal {}: stopping", signals.signal_number());
  pipeline.stop();
  const auto s = pipeline.status();
  spdlog::info("stopped: {}", status_line(s));
  if (auto err = pipeline.fatal_error()) throw CommandError(*err);
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run",
                                 "Run the service (default: the synthetic rig, HTTP on "
                                 "127.0.0.1:8080)");
  // Not in --help: the watchdog test's fault (PipelineOptions::hang_after_frames).
  cmd->add_option("--fault-hang-after", args->fault_hang_after,
                  "Fault injection: hang the processing loop after N frames")
      ->group("");
  cmd->add_option("--fault-hang", args->fault_hang,
                  "Fault injection: THREAD:N, the thread (light, output, http, rtsp) hangs at "
                  "its N-th heartbeat")
      ->group("");
  cmd->add_option("--config", args->config_path, "TOML configuration (docs/configuration.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--board", args->board,
                  "Board file under the config: name, directory or file (docs/boards.md)");
  cmd->add_option("--source", args->source, "Rig: sim[:options], replay:DIR, tum:DIR");
  cmd->add_option("--frames", args->frames, "Stop after N frames")->check(CLI::PositiveNumber);
  cmd->add_option("--out", args->out_dir, "Also write the composite frames to DIR");
  cmd->add_flag("--matte", args->matte, "With --out: write the occlusion matte too");
  cmd->add_option("--occlusion", args->occlusion, "Occlusion method (direct1, direct2, cvf, ...)");
  cmd->add_option("--address", args->address, "HTTP bind address (default 127.0.0.1)");
  cmd->add_option("--port", args->port, "HTTP port (default 8080, 0 = any free port)")
      ->check(CLI::Range(0, 65535));
  cmd->add_option("--allow-origin", args->allow_origin,
                  "HTTP: an origin whose scripts may read the responses (Access-Control-Allow-"
                  "Origin; [http] cors_origin, ustreamer's flag)");
  cmd->callback([args] { run(*args); });
}

}  // namespace probeless::cli

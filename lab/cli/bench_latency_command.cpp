// probeless bench latency: glass-to-glass latency of each output path on loopback (issue #22
// item 4; docs/outputs.md "Glass-to-glass latency"). A `probeless run` on a source that
// stamps each frame's capture time into its picture (`sim:stamp=1`, core/capture_stamp.hpp),
// with HTTP and RTSP on; a client per path in this process receives the stream, decodes every
// frame to RGB and reads the stamp back: latency = decoded (CLOCK_MONOTONIC, this process)
// minus capture (CLOCK_MONOTONIC, the source's frame timestamp). The paths are measured one
// after the other, each alone, on the same service. A frame whose stamp does not read is
// counted by reason, never timed.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <variant>

#include "app/outputs/webrtc_output.hpp"
#include "base/stage_stats.hpp"
#include "core/capture_stamp.hpp"
#include "lab/bench/mjpeg_receiver.hpp"
#include "lab/bench/rtsp_receiver.hpp"
#include "lab/bench/service_under_test.hpp"
#include "lab/bench/whep_receiver.hpp"
#include "lab/cli/lab_commands.hpp"

namespace probeless::cli {
namespace {

using namespace std::chrono_literals;

struct BenchLatencyOptions {
  double seconds = 10;  // per path
  double warmup_s = 5;  // service frames before the first path, and per path once it plays
  std::string source = "sim:stamp=1";
  bool prerender = false;
  std::string json;
};

// With --prerender, the sim's frames for the whole run rendered before its clock starts
// (docs/sim.md `prerender`), without truth (1.5 MB a frame instead of 2.5): the camera then
// costs the machine no CPU, as a real camera's exposure and readout cost the appliance none,
// and what is measured is the appliance. 30 frames a second of the run, with a margin for the
// service's start and each path's wait for its first frame.
std::string source_spec(const BenchLatencyOptions& o) {
  if (!o.prerender) return o.source;
  if (o.source.rfind("sim", 0) != 0)
    throw CommandError("bench latency: --prerender needs a sim source, not " + o.source);
  const double run_s = 3 * o.warmup_s + 2 * o.seconds + 20;
  const auto frames = static_cast<long>(std::ceil(run_s * 30));
  return o.source + (o.source == "sim" ? ":" : ",") +
         "truth=0,fisheye_repeat=1,fisheye_scenes=24,prerender=" + std::to_string(frames);
}

// Where the service's outputs are, as the paths' receivers need them.
struct ServiceEndpoints {
  int http_port = 0;
  std::string rtsp_url;  // empty: RTSP off
  bool whep = false;     // the service has its WebRTC output behind /whep
  std::string whep_off;  // why not, when it has not
};

// One output path: its receiver, or why it cannot be measured (reported as "skipped").
// A new output is one more entry in latency_paths().
using OpenedReceiver = std::variant<std::unique_ptr<lab::FrameReceiver>, std::string>;
struct LatencyPath {
  std::string name;
  std::function<OpenedReceiver(const ServiceEndpoints&)> open;
};

std::vector<LatencyPath> latency_paths() {
  return {
      {"mjpeg",
       [](const ServiceEndpoints& s) -> OpenedReceiver {
         return std::make_unique<lab::MjpegReceiver>(s.http_port);
       }},
      {"rtsp",
       [](const ServiceEndpoints& s) -> OpenedReceiver {
         if (s.rtsp_url.empty()) return std::string("the service has no RTSP output");
         return std::make_unique<lab::RtspReceiver>(s.rtsp_url);
       }},
      {"webrtc",
       [](const ServiceEndpoints& s) -> OpenedReceiver {
         if (!s.whep) return s.whep_off;
         return std::make_unique<lab::WhepReceiver>(s.http_port);
       }},
  };
}

// p50/p99 by nearest rank, as every bench reports them (base/stage_stats.hpp summarize()).
nlohmann::json summary(const std::vector<double>& ms) {
  if (ms.empty()) return nullptr;
  const TimingSummary s = summarize(ms);
  const auto [lo, hi] = std::minmax_element(ms.begin(), ms.end());
  return {{"p50_ms", s.p50_ms}, {"p99_ms", s.p99_ms}, {"min_ms", *lo}, {"max_ms", *hi}};
}

// Receives for `warmup_s` once the first stamped frame is in (the RTSP media starts at a
// keyframe, the decoders settle), then times every frame for `seconds`.
nlohmann::json measure(lab::FrameReceiver& receiver, const BenchLatencyOptions& o) {
  const auto first_deadline = std::chrono::steady_clock::now() + 30s;
  for (;;) {
    if (std::chrono::steady_clock::now() > first_deadline)
      throw CommandError("bench latency: no frame with a readable stamp within 30 s");
    if (auto f = receiver.next(1s); f && read_capture_stamp(f->image).result == StampRead::Ok)
      break;
  }
  const auto warm_end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(o.warmup_s);
  while (std::chrono::steady_clock::now() < warm_end) (void)receiver.next(100ms);

  std::vector<double> latency_ms, service_ms;
  std::map<std::string, int> unreadable;
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  const auto end = start + std::chrono::duration<double>(o.seconds);
  while (std::chrono::steady_clock::now() < end) {
    auto f = receiver.next(1s);
    if (!f) continue;
    ++frames;
    const StampReading r = read_capture_stamp(f->image);
    if (r.result != StampRead::Ok) {
      ++unreadable[to_string(r.result)];
      continue;
    }
    const TimestampNs captured = unwrap_stamp(r.micros, f->decoded_ns);
    latency_ms.push_back(static_cast<double>(f->decoded_ns - captured) * 1e-6);
    if (f->service_ms) service_ms.push_back(*f->service_ms);
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json out = summary(latency_ms);
  if (out.is_null()) out = nlohmann::json::object();
  out["frames"] = frames;
  out["timed"] = latency_ms.size();
  out["unreadable"] = unreadable;
  out["fps"] = frames / elapsed;
  // MJPEG says when each part left the service (ustreamer's X-UStreamer-Latency): the
  // service's share of the latency, the rest being the socket and the client's decode.
  if (auto s = summary(service_ms); !s.is_null())
    out["service"] = {{"p50_ms", s["p50_ms"]}, {"p99_ms", s["p99_ms"]}};
  return out;
}

std::array<double, 3> load_average() {
  std::array<double, 3> load{};
  std::ifstream("/proc/loadavg") >> load[0] >> load[1] >> load[2];
  return load;
}

void run_bench(const BenchLatencyOptions& o) {
  const auto config = std::filesystem::temp_directory_path() /
                      fmt::format("probeless-bench-latency-{}.toml", getpid());
  // WebRTC only where GStreamer has it: without, the service would not start at all.
  const std::string webrtc_missing = webrtc_missing_plugins();
  std::ofstream(config) << "[rtsp]\nenabled = true\nport = 0\n"
                        << (webrtc_missing.empty() ? "[webrtc]\nenabled = true\n" : "");
  const std::string source = source_spec(o);
  lab::ServiceUnderTest service({"--source", source, "--config", config.string()});
  std::filesystem::remove(config);
  ServiceEndpoints endpoints;
  endpoints.http_port = service.port();
  if (const auto s = service.status(); s.contains("rtsp"))
    endpoints.rtsp_url = s["rtsp"].value("url", "");
  endpoints.whep = webrtc_missing.empty();
  endpoints.whep_off = "no WebRTC in this GStreamer: " + webrtc_missing;
  std::cout << fmt::format("bench latency: service pid {} on {}, http port {}, {}\n", service.pid(),
                           source, endpoints.http_port,
                           endpoints.rtsp_url.empty() ? "no RTSP" : endpoints.rtsp_url)
            << std::flush;
  // The first frames build the OpenCL programs and the tracker finds its feet.
  const auto deadline = std::chrono::steady_clock::now() + 120s;
  while (service.frames_processed() < 10 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(200ms);
  std::this_thread::sleep_for(std::chrono::duration<double>(o.warmup_s));

  const auto load_before = load_average();
  nlohmann::json report = nlohmann::json::object();
  for (const LatencyPath& path : latency_paths()) {
    OpenedReceiver opened = path.open(endpoints);
    if (auto* reason = std::get_if<std::string>(&opened)) {
      report[path.name] = {{"skipped", *reason}};
      std::cout << fmt::format("  {}: skipped: {}\n", path.name, *reason);
      continue;
    }
    auto& receiver = std::get<std::unique_ptr<lab::FrameReceiver>>(opened);
    report[path.name] = measure(*receiver, o);
    receiver.reset();  // the next path is measured alone
    const auto& r = report[path.name];
    std::cout << fmt::format("  {}: p50 {:.1f} ms, p99 {:.1f} ms over {} frames ({} unreadable)\n",
                             path.name, r.value("p50_ms", -1.0), r.value("p99_ms", -1.0),
                             r["timed"].get<int>(), r["frames"].get<int>() - r["timed"].get<int>())
              << std::flush;
  }
  if (!service.alive()) throw CommandError("bench latency: the service died");
  const nlohmann::json status = service.status();
  const auto load_after = load_average();
  report["details"] = {{"source", source},
                       {"clock",
                        "CLOCK_MONOTONIC: the source's frame timestamp, stamped into the picture, "
                        "against this process's clock as each frame is decoded"},
                       {"seconds_per_path", o.seconds},
                       {"service_fps", status.value("fps", 0.0)},
                       {"service_stages", status.value("stages", nlohmann::json::object())},
                       {"load_average_before", load_before},
                       {"load_average_after", load_after}};
  std::cout << report.dump(2) << "\n";
  if (!o.json.empty()) write_json_report(o.json, report);
}

}  // namespace

void add_bench_latency_command(CLI::App& bench) {
  auto o = std::make_shared<BenchLatencyOptions>();
  auto* cmd = bench.add_subcommand(
      "latency",
      "Glass-to-glass latency of MJPEG, RTSP (and WebRTC) on loopback: capture time stamped "
      "into the picture, read back from each decoded frame");
  cmd->add_option("--seconds", o->seconds, "Frames timed per path (10 s)")
      ->check(CLI::Range(0.5, 3600.0));
  cmd->add_option("--warmup", o->warmup_s,
                  "Seconds of service frames before timing, and per path once it plays (5)")
      ->check(CLI::Range(0.0, 600.0));
  cmd->add_option("--source", o->source,
                  "A source that stamps its frames (sim:stamp=1; a recording: "
                  "replay:DIR?rebase=1,stamp=1)");
  cmd->add_flag("--prerender", o->prerender,
                "The sim's frames rendered before timing (truth=0,prerender=N): the camera "
                "costs no CPU; about 1.5 MB a frame, 2.5 GB at the defaults");
  cmd->add_option("--json", o->json, "Write the report as JSON");
  cmd->callback([o] { run_bench(*o); });
}

}  // namespace probeless::cli

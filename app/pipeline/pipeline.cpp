#include "app/pipeline/pipeline.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "app/outputs/banner.hpp"
#include "app/outputs/jpeg_encoder.hpp"
#include "app/pipeline/frame_finisher.hpp"
#include "app/pipeline/frame_processor.hpp"
#include "app/pipeline/light_capture.hpp"
#include "app/pipeline/output_factory.hpp"
#include "app/pipeline/scene_objects.hpp"
#include "app/pipeline/thread_name.hpp"
#include "drivers/trigger/gpio_strobe.hpp"
#include "drivers/trigger/gpio_trigger.hpp"

namespace probeless {
namespace {

using namespace std::chrono_literals;

}  // namespace

Pipeline::Pipeline(ServiceConfig config, Rig rig, PipelineOptions options)
    : config_(std::move(config)),
      rig_(std::move(rig)),
      options_(std::move(options)),
      heartbeats_(options_.notifier ? ServiceWatchdog::stale_after(*options_.notifier)
                                    : std::chrono::milliseconds(2000)) {
  if (!rig_.rgbd) throw std::invalid_argument("pipeline: the rig has no RGB-D source");
  if (config_.world.anchor != "rig") {
    // The world is the marker's or the floor's (docs/tracking.md "World anchoring"): the
    // objects stand at its origin by default, and the rig's room is in the rig's world.
    rig_.scene.object_anchor = Eigen::Vector3d::Zero();
    rig_.scene.room.reset();
  }
  place_objects(config_.objects, rig_.scene);
  if (options_.lossless) stats_.keep_all(true);
}

Pipeline::~Pipeline() {
  stop();
}

void Pipeline::start() {
  started_ns_ = monotonic_now_ns();
  last_rgbd_ns_ = started_ns_;  // "no signal" counts from the start, not from 1970
  if (!options_.hang_thread.empty())
    heartbeats_.wedge_after(options_.hang_thread, options_.hang_after_beats);
  open_outputs();
  if (rig_.fisheye && config_.bracket_enabled) {
    bracket_ = std::make_unique<BracketSequencer>(config_.bracket);
    if (!config_.trigger_chip.empty()) {
      GpioTriggerConfig trigger;
      trigger.chip = config_.trigger_chip;
      trigger.line = static_cast<unsigned>(config_.trigger_line);
      trigger_ = std::make_unique<GpioTrigger>(trigger);  // a missing chip fails start()
    }
  }
  if (rig_.fisheye && !config_.strobe_chip.empty()) {
    GpioStrobeConfig strobe;
    strobe.chip = config_.strobe_chip;
    strobe.line = static_cast<unsigned>(config_.strobe_line);
    strobe.edge = parse_strobe_edge(config_.strobe_edge);
    strobe_ = std::make_unique<GpioStrobe>(strobe);  // so does a missing strobe chip
  }
  if (rig_.fisheye && config_.light_enabled) {
    try {
      light_ = std::make_unique<LightCapture>(config_, rig_.calibration, rig_.scene, poses_);
    } catch (const std::invalid_argument& e) {
      spdlog::warn("light capture off: {}", e.what());
    }
  }
  threads_.emplace_back([this](std::stop_token s) {
    name_this_thread("pl-rgbd");
    capture_rgbd(s);
  });
  if (light_)
    threads_.emplace_back([this](std::stop_token s) { light_->run(s, stats_, heartbeats_); });
  if (rig_.fisheye)
    threads_.emplace_back([this](std::stop_token s) {
      name_this_thread("pl-fisheye");
      capture_fisheye(s);
    });
  threads_.emplace_back([this](std::stop_token s) { process(s); });
  threads_.emplace_back([this](std::stop_token s) {
    name_this_thread("pl-output");
    output_loop(s);
  });
  if (options_.notifier)
    watchdog_ = std::make_unique<ServiceWatchdog>(*options_.notifier, heartbeats_);
}

void Pipeline::open_outputs() {
  SharedOutputParts shared;  // RTSP and WebRTC: one H.264 encoder, held by both
  for (const std::string_view name : kOutputNames) {
    if (!options_.serve_http && (name == "http" || name == "rtsp" || name == "webrtc")) continue;
    if (auto output = make_output(
            name, config_, [this] { return status(); }, &shared)) {
      std::lock_guard lock(outputs_mutex_);
      outputs_.push_back(std::move(output));
    }
  }
  std::lock_guard lock(outputs_mutex_);
  for (const auto& output : options_.outputs)
    if (output) outputs_.push_back(output);
  // WHEP offers reach the WebRTC output through the HTTP server.
  std::shared_ptr<HttpServer> http;
  std::shared_ptr<WebRtcOutput> webrtc;
  for (const auto& output : outputs_) {
    if (auto h = std::dynamic_pointer_cast<HttpServer>(output)) http = h;
    if (auto w = std::dynamic_pointer_cast<WebRtcOutput>(output)) webrtc = w;
  }
  if (http && webrtc) http->set_whep(webrtc);
  for (const auto& output : outputs_) {
    output->watch(heartbeats_);  // the HTTP and RTSP loops beat from a timer of their own
    const OutputNeeds n = output->needs();
    if (n.jpeg)
      needs_.jpeg_quality =
          needs_.jpeg ? std::max(needs_.jpeg_quality, n.jpeg_quality) : n.jpeg_quality;
    needs_.jpeg = needs_.jpeg || n.jpeg;
    needs_.colour = needs_.colour || n.colour;
    needs_.matte = needs_.matte || n.matte;
  }
}

void Pipeline::stop() {
  {
    std::lock_guard lock(state_mutex_);
    if (stopped_) return;
    stopped_ = true;
  }
  watchdog_.reset();
  heartbeats_.release_wedged();  // a thread wedged by fault injection can then be joined
  for (auto& t : threads_) t.request_stop();
  rgbd_credit_.release();  // a lossless capture thread may wait for a credit
  rgbd_slot_.close();
  output_.close();
  threads_.clear();  // jthread joins
  for (const auto& output : outputs_) output->stop();
  state_changed_.notify_all();
}

bool Pipeline::wait_first_frame(std::chrono::milliseconds timeout) {
  std::unique_lock lock(state_mutex_);
  state_changed_.wait_for(lock, timeout, [&] { return first_out_ || fatal_ || finished_; });
  return first_out_;
}

bool Pipeline::wait_finished(std::chrono::milliseconds timeout) {
  std::unique_lock lock(state_mutex_);
  return state_changed_.wait_for(lock, timeout, [&] { return finished_.load(); });
}

std::optional<std::string> Pipeline::fatal_error() const {
  std::lock_guard lock(state_mutex_);
  return fatal_;
}

std::string Pipeline::url_of(std::string_view name) const {
  std::lock_guard lock(outputs_mutex_);
  for (const auto& output : outputs_)
    if (output->name() == name) return output->url();
  return {};
}

std::string Pipeline::url() const {
  return url_of("http");
}

std::string Pipeline::rtsp_url() const {
  return url_of("rtsp");
}

void Pipeline::fail(const std::string& what) {
  spdlog::error("pipeline: {}", what);
  {
    std::lock_guard lock(state_mutex_);
    if (!fatal_) fatal_ = what;
  }
  finish();
}

void Pipeline::finish() {
  finished_ = true;
  state_changed_.notify_all();
}

void Pipeline::capture_rgbd(std::stop_token stop) {
  RgbdSource& source = *rig_.rgbd;
  SourceState last_state = SourceState::Streaming;
  while (!stop.stop_requested()) {
    if (options_.lossless) {
      while (!rgbd_credit_.try_acquire_for(100ms))
        if (stop.stop_requested()) return;
      if (stop.stop_requested()) return;
    }
    RgbdFrame frame;
    const auto t0 = std::chrono::steady_clock::now();
    const ReadResult r = source.read(frame, 100ms);
    if (r == ReadResult::Frame) {
      stats_.record("capture_rgbd", ms_since(t0));
      ++rgbd_in_;
      if (light_) light_->offer_rgbd(frame);  // its poses come from processing (poses_)
      last_rgbd_ns_ = monotonic_now_ns();
      rgbd_slot_.publish(std::move(frame));
      continue;
    }
    if (options_.lossless) rgbd_credit_.release();
    if (r == ReadResult::EndOfStream) {
      spdlog::info("{}: end of stream after {} frames", source.name(), rgbd_in_.load());
      rgbd_ended_ = true;
      rgbd_slot_.close();
      return;
    }
    const SourceState state = source.state();
    if (state != last_state) {
      spdlog::warn("{}: {}{}", source.name(), to_string(state),
                   source.last_error().empty() ? "" : " (" + source.last_error() + ")");
      last_state = state;
    }
    // Error: the driver retries its device; wait a little rather than spin on it.
    if (r == ReadResult::Error) std::this_thread::sleep_for(100ms);
  }
}

void Pipeline::capture_fisheye(std::stop_token stop) {
  FisheyeSource& source = *rig_.fisheye;
  bool armed = false;  // the next frame's exposure is set (and triggered) once per frame
  while (!stop.stop_requested()) {
    if (bracket_ && !armed) {
      start_next_frame(*bracket_, source, trigger_.get());
      armed = true;
    }
    FisheyeFrame frame;
    const auto t0 = std::chrono::steady_clock::now();
    const ReadResult r = source.read(frame, 100ms);
    if (r == ReadResult::EndOfStream) return;
    if (r == ReadResult::Error) std::this_thread::sleep_for(100ms);
    if (r != ReadResult::Frame) continue;
    stats_.record("capture_fisheye", ms_since(t0));
    if (strobe_ && !strobe_failed_) stamp_fisheye_frame(frame);
    if (bracket_) {
      // Saturated and black counts steer L and H (docs/bracketing.md). On the CPU here: a
      // 512 px frame takes well under a millisecond; the OpenCL reduction replaces it when
      // the light stage keeps the frame on the device.
      const auto t1 = std::chrono::steady_clock::now();
      bracket_->observe(frame.exposure,
                        count_exposure(frame.raw, frame.bit_depth, frame.black_level));
      stats_.record("exposure_count", ms_since(t1));
      armed = false;
    }
    std::lock_guard lock(fisheye_mutex_);
    if (bracket_) {
      bracket_stops_[0] = bracket_->low_stop();
      bracket_stops_[1] = bracket_->medium_stop();
      bracket_stops_[2] = bracket_->high_stop();
    }
    fisheye_exposure_ = frame.exposure;
    ++fisheye_in_;
    if (light_) light_->push(std::move(frame));  // the light thread keeps a bracket cycle
  }
}

// One frame in flight (trigger, read, trigger, ...): the newest queued edge is the strobe of
// the frame just read, the kernel's CLOCK_MONOTONIC time of its exposure start.
void Pipeline::stamp_fisheye_frame(FisheyeFrame& frame) {
  try {
    // No wait: a sensor's strobe edge (exposure start) is queued long before its frame is
    // read out.
    if (stamp_with_strobe(*strobe_, frame, std::chrono::nanoseconds(0))) ++strobe_stamped_;
  } catch (const std::runtime_error& e) {
    spdlog::error("{}; fisheye frames keep their driver timestamps", e.what());
    strobe_failed_ = true;
  }
}

void Pipeline::process(std::stop_token stop) {
  try {
    LightSource light;
    if (light_) light = [this] { return light_->latest_light(); };
    FrameProcessor processor(config_, rig_.calibration, options_.keep_matte || needs_.matte,
                             std::move(light), poses_);
    {
      std::lock_guard lock(state_mutex_);
      occlusion_name_ = processor.occlusion_method();
      device_name_ = processor.device_description();
    }
    spdlog::info("processing on {}, occlusion '{}'", processor.device_description(),
                 processor.occlusion_method());
    // Named after the OpenCL context is built: PoCL's worker threads take the name of the
    // thread that starts them, and `bench pipeline` counts them apart.
    name_this_thread("pl-process");
    process_loop(stop, processor);
  } catch (const std::exception& e) {
    fail(e.what());
  }
}

bool Pipeline::publish(CompositeFrame out, const world::LocaliserStatus& status,
                       std::stop_token stop) {
  {
    nlohmann::json tracking = status.to_json();
    std::lock_guard lock(state_mutex_);
    tracking_ = std::move(tracking);
  }
  {
    std::lock_guard lock(last_good_mutex_);
    last_good_ = out;
  }
  if (options_.lossless)
    while (output_taken_.load() < output_published_.load() && !stop.stop_requested())
      std::this_thread::sleep_for(1ms);
  output_published_ = output_.publish(std::move(out));
  fps_.tick(monotonic_now_ns());
  const auto n = ++processed_;
  if (options_.hang_after_frames >= 0 &&
      static_cast<std::int64_t>(n) >= options_.hang_after_frames) {
    // The processing thread then waits for room that never comes, and its heartbeat goes
    // stale: what a frame stuck in a driver or OpenCL call does.
    spdlog::warn("fault injection: the processing loop hangs after {} frames", n);
    while (!stop.stop_requested()) std::this_thread::sleep_for(50ms);
    return false;
  }
  if (config_.max_frames > 0 && static_cast<std::int64_t>(n) >= config_.max_frames) {
    finish();
    return false;
  }
  return true;
}

void Pipeline::process_loop(std::stop_token stop, FrameProcessor& processor) {
  LatestFrame<RgbdFrame>::Sequence seen = 0;
  auto last_banner = std::chrono::steady_clock::now() - 1h;
  // Watched from the first frame out: FrameProcessor's construction and first frame build
  // the OpenCL programs (seconds each on PoCL, longer on a loaded board than WatchdogSec).
  Heartbeat heartbeat;
  // Publishes each frame as soon as the device has finished it (frame_finisher.hpp), while
  // this thread locates and renders the next: at most kFrameSlots frames on the way. Declared
  // after `processor` is made and destroyed before it: its frames wait for the device.
  FrameFinisher finisher(
      processor, stats_,
      [this](CompositeFrame out, const world::LocaliserStatus& status, std::stop_token s) {
        return publish(std::move(out), status, s);
      },
      [this](const std::string& what) { fail(what); });

  while (!stop.stop_requested()) {
    const auto now = std::chrono::steady_clock::now();
    heartbeat.beat();  // at least every 50 ms (take_newer's timeout) while the loop turns
    if (!heartbeat && processed_.load() > 0) heartbeat = heartbeats_.add("processing");
    auto item = rgbd_slot_.take_newer(seen, 50ms);
    if (!item) {
      if (rgbd_ended_) {
        finisher.drain(stop);  // the stream's last frames go out before the pipeline ends
        return finish();
      }
      const auto silent_ns = monotonic_now_ns() - last_rgbd_ns_.load();
      if (silent_ns > config_.no_signal_after_ms * 1'000'000LL) {
        if (!no_signal_.exchange(true))
          spdlog::warn("{}: no signal for {} ms: serving the last frame marked NO SIGNAL",
                       rig_.rgbd->name(), silent_ns / 1'000'000);
        if (now - last_banner > 200ms && finisher.on_the_way() == 0) {  // 5 Hz keeps viewers'
          publish_no_signal(to_string(rig_.rgbd->state()));             // streams alive
          last_banner = now;
        }
      }
      continue;
    }
    seen = item->sequence;
    if (options_.lossless) rgbd_credit_.release();
    if (no_signal_.exchange(false)) spdlog::info("{}: signal back", rig_.rgbd->name());

    // On the heap and never moved: the device reads the frame's images until it is finished.
    auto submitted = std::make_unique<FrameFinisher::Submitted>();
    submitted->frame = std::move(item->value);
    const FrameProcessor::Located located = processor.locate(submitted->frame, stats_);
    submitted->status = located.status;
    // Located first, then the wait for room: the tracking overlaps the device's work on the
    // frames before (waiting first cost 10-15 % of the frame rate, docs/performance.md).
    if (!finisher.wait_for_room(stop)) return;
    submitted->work = processor.submit(submitted->frame, located, stats_);
    finisher.push(std::move(submitted));
  }
}

void Pipeline::publish_no_signal(const std::string& state) {
  CompositeFrame f;
  std::optional<CompositeFrame> last_good;
  {
    std::lock_guard lock(last_good_mutex_);
    last_good = last_good_;
  }
  if (last_good) {
    f = *last_good;
    auto colour = std::make_shared<ImageRGB8>(*last_good->colour);
    draw_no_signal(*colour, rig_.rgbd->name(), state);
    f.colour = std::move(colour);
  } else {  // nothing good yet: a black frame of the camera's size says it all the same
    auto colour =
        std::make_shared<ImageRGB8>(rig_.calibration.rgb.width(), rig_.calibration.rgb.height());
    draw_no_signal(*colour, rig_.rgbd->name(), state);
    f.colour = std::move(colour);
  }
  f.no_signal = true;
  output_published_ = output_.publish(std::move(f));
}

void Pipeline::output_loop(std::stop_token stop) {
  // One encode per frame whatever the number of outputs that want it, none when none does.
  std::optional<JpegEncoder> encoder;
  if (needs_.jpeg) encoder.emplace(needs_.jpeg_quality);
  LatestFrame<CompositeFrame>::Sequence seen = 0;
  Heartbeat heartbeat = heartbeats_.add("output");
  while (!stop.stop_requested()) {
    heartbeat.beat();  // at least every 100 ms (wait_newer's timeout)
    auto item = output_.wait_newer(seen, 100ms, stop);
    if (!item) continue;
    seen = item->sequence;
    output_taken_ = seen;
    const CompositeFrame& f = item->value;
    OutputFrame out;
    out.timestamp_ns = f.timestamp_ns;
    out.colour = f.colour;
    if (needs_.matte) out.matte = f.alpha;
    out.no_signal = f.no_signal;
    // The outputs of raw frames first (the H.264 encoder's queue, the screen, the files):
    // they need not wait for the JPEG.
    for (const auto& output : outputs_)
      if (!output->needs().jpeg) output->offer(out);
    if (encoder) {
      const auto t0 = std::chrono::steady_clock::now();
      out.jpeg = encoder->encode_shared(*f.colour);
      ++jpeg_encodes_;
      if (!f.no_signal) stats_.record("encode", ms_since(t0));
      for (const auto& output : outputs_)
        if (output->needs().jpeg) output->offer(out);
    }
    const auto n = ++encoded_;
    if (n == 1) {
      std::lock_guard lock(state_mutex_);
      first_out_ = true;
      state_changed_.notify_all();
    }
  }
}

nlohmann::json Pipeline::status() const {
  const auto now = monotonic_now_ns();
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, s] : stats_.summaries())
    stages[name] = {{"p50_ms", s.p50_ms}, {"p99_ms", s.p99_ms}};
  nlohmann::json j;
  std::string state = "running";
  if (fatal_error())
    state = "failed";
  else if (finished_)
    state = "finished";
  else if (no_signal_)
    state = "no_signal";
  else if (processed_ == 0)
    state = "starting";
  j["state"] = state;
  j["fps"] = fps_.rate_hz(now);
  j["uptime_s"] = static_cast<double>(now - started_ns_) * 1e-9;
  j["frames"] = {{"processed", processed_.load()},
                 {"out", encoded_.load()},
                 {"rgbd_in", rgbd_in_.load()},
                 {"rgbd_dropped", rgbd_slot_.drops()}};
  {
    std::lock_guard lock(fisheye_mutex_);
    j["frames"]["fisheye_in"] = fisheye_in_;
    if (fisheye_exposure_) {
      const ExposureStamp& e = *fisheye_exposure_;
      j["fisheye_exposure"] = {{"level", to_string(e.level)},
                               {"time_ms", e.exposure.time_s * 1e3},
                               {"gain_db", e.exposure.gain_db},
                               {"cycle", e.cycle}};
    }
    if (bracket_)
      j["bracket"] = {{"low_stop", bracket_stops_[0]},
                      {"medium_stop", bracket_stops_[1]},
                      {"high_stop", bracket_stops_[2]},
                      {"trigger", trigger_ ? trigger_->name() : std::string("none")}};
    if (strobe_)
      j["strobe"] = {{"line", strobe_->name()},
                     {"stamped", strobe_stamped_.load()},
                     {"failed", strobe_failed_.load()}};
  }
  j["stages"] = stages;
  nlohmann::json sources;
  sources["rgbd"] = {
      {"name", rig_.rgbd->name()},
      {"state", no_signal_ ? std::string("no_signal") : std::string(to_string(rig_.rgbd->state()))},
      {"last_error", rig_.rgbd->last_error()}};
  if (rig_.fisheye)
    sources["fisheye"] = {{"name", rig_.fisheye->name()},
                          {"state", to_string(rig_.fisheye->state())},
                          {"last_error", rig_.fisheye->last_error()}};
  j["sources"] = sources;
  j["light"] = light_ ? light_->status() : nlohmann::json{{"state", "off"}};
  j["watchdog"] = heartbeats_.to_json();
  {
    std::lock_guard lock(state_mutex_);
    j["occlusion"] = occlusion_name_;
    j["tracking"] =
        tracking_.is_null()
            ? nlohmann::json{{"state", "off"},
                             {"method", config_.tracking.method},
                             {"pose", nullptr},
                             {"keyframes", 0},
                             {"lost_count", 0},
                             {"anchor", {{"kind", config_.world.anchor}, {"found", false}}}}
            : tracking_;
    j["device"] = device_name_;
    if (fatal_) j["error"] = *fatal_;
  }
  {
    std::lock_guard lock(outputs_mutex_);
    for (const auto& output : outputs_) output->add_status(j);
  }
  return j;
}

}  // namespace probeless

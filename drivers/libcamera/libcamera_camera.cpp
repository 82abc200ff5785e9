#include "drivers/libcamera/libcamera_camera.hpp"

#include <fmt/format.h>
#include <libcamera/libcamera.h>
#include <sys/mman.h>
#include <sys/sysmacros.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "drivers/libcamera/libcamera_format_map.hpp"

namespace probeless::libcam {

namespace lc = libcamera;

struct LibcameraCamera::Mapping {
  void* base = MAP_FAILED;
  std::size_t length = 0;
  std::span<const std::uint8_t> bytes;  // plane 0: every converted format is one plane
};

namespace {

// Cameras whose device vanished without a hotplug disconnect, kept alive on purpose (see
// LibcameraCamera::abandon); libcamera 0.0.3 keeps listing them.
struct Abandoned {
  std::shared_ptr<lc::Camera> camera;
  std::unique_ptr<lc::FrameBufferAllocator> allocator;
  std::vector<std::unique_ptr<lc::Request>> requests;
};
std::mutex abandoned_mutex;
std::vector<Abandoned>& abandoned() {
  static auto* list = new std::vector<Abandoned>;  // never destroyed: libcamera points into it
  return *list;
}
bool is_abandoned(const lc::Camera* camera) {
  std::lock_guard lock(abandoned_mutex);
  return std::any_of(abandoned().begin(), abandoned().end(),
                     [&](const Abandoned& a) { return a.camera.get() == camera; });
}

std::string read_line(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

bool offers(const lc::Camera& camera, const lc::ControlId& id) {
  return camera.controls().find(&id) != camera.controls().end();
}

// The best convertible format among those `config` offers at any size (or the asked one),
// with the role whose configuration offered it. Raw first: some pipelines list Bayer only
// for the Raw role.
struct Choice {
  lc::StreamRole role = lc::StreamRole::Viewfinder;
  lc::PixelFormat format;
};

Choice choose_format(lc::Camera& camera, const LibcameraOptions& o) {
  std::optional<Choice> best;
  std::vector<std::string> offered;
  const lc::PixelFormat wanted =
      o.format.empty() ? lc::PixelFormat{} : lc::PixelFormat::fromString(o.format);
  if (!o.format.empty() && (!wanted.isValid() || format_rank(wanted) < 0))
    throw ConfigError(
        fmt::format("libcamera option 'format': '{}' is not a format the source "
                    "converts (SRGGB12, SRGGB10, SRGGB8, BGR888, RGB888, YUYV, ...)",
                    o.format));
  for (const auto role : {lc::StreamRole::Raw, lc::StreamRole::Viewfinder}) {
    const auto config = camera.generateConfiguration({role});
    if (!config || config->empty()) continue;
    for (const lc::PixelFormat& pf : config->at(0).formats().pixelformats()) {
      offered.push_back(pf.toString());
      const int rank = format_rank(pf);
      if (rank < 0 || (wanted.isValid() && pf != wanted)) continue;
      if (!best || rank < format_rank(best->format)) best = Choice{role, pf};
    }
  }
  if (!best) {
    std::sort(offered.begin(), offered.end());
    offered.erase(std::unique(offered.begin(), offered.end()), offered.end());
    throw ConfigError(fmt::format("libcamera camera '{}' offers no {}; it offers: {}", camera.id(),
                                  o.format.empty() ? "convertible format" : o.format,
                                  fmt::join(offered, ", ")));
  }
  return *best;
}

}  // namespace

std::string camera_ids(lc::CameraManager& manager) {
  std::vector<std::string> ids;
  for (const auto& c : manager.cameras()) ids.push_back("'" + c->id() + "'");
  return ids.empty() ? std::string("none") : fmt::format("{}", fmt::join(ids, ", "));
}

LibcameraCamera::LibcameraCamera(std::shared_ptr<lc::CameraManager> manager,
                                 const LibcameraOptions& o, const ExposureStamp& initial)
    : manager_(std::move(manager)) {
  if (o.camera_id.empty()) {
    const auto cameras = manager_->cameras();
    if (cameras.empty()) throw DeviceError("libcamera finds no camera");
    camera_ = cameras.front();
  } else {
    camera_ = manager_->get(o.camera_id);
    if (!camera_)
      throw DeviceError(fmt::format("no libcamera camera '{}' (cameras: {})", o.camera_id,
                                    camera_ids(*manager_)));
  }
  info_.camera_id = camera_->id();
  if (is_abandoned(camera_.get())) {
    camera_.reset();
    throw DeviceError(
        fmt::format("libcamera camera '{}' is gone (its device nodes vanished; "
                    "libcamera 0.0.3 lists it until the process restarts)",
                    info_.camera_id));
  }
  try {
    if (const int ret = camera_->acquire(); ret < 0)
      throw DeviceError(
          fmt::format("libcamera camera '{}' cannot be acquired (error {}: in use "
                      "by another process?)",
                      info_.camera_id, ret));
    acquired_ = true;
    // Only once the camera is ours: the Camera object is shared, and a slot connected while
    // another source streams it is called for that source's requests on libcamera's thread
    // (vm_vimc crashed so under load: "Camera in Running state trying acquire()", then
    // SIGSEGV in our completion handler with another source's request).
    camera_->disconnected.connect(this, &LibcameraCamera::on_disconnected);
    camera_->requestCompleted.connect(this, &LibcameraCamera::on_request_completed);
    find_video_nodes();

    const Choice choice = choose_format(*camera_, o);
    auto config = camera_->generateConfiguration({choice.role});
    lc::StreamConfiguration& sc = config->at(0);
    sc.pixelFormat = choice.format;
    sc.size = lc::Size(static_cast<unsigned>(o.width), static_cast<unsigned>(o.height));
    sc.bufferCount = static_cast<unsigned>(o.buffers);
    if (config->validate() == lc::CameraConfiguration::Invalid)
      throw ConfigError(fmt::format("libcamera camera '{}' rejects {} {}x{}", info_.camera_id,
                                    choice.format.toString(), o.width, o.height));
    // The calibration is for one size: an adjusted size or format is an error, not a guess.
    if (sc.pixelFormat != choice.format || sc.size.width != static_cast<unsigned>(o.width) ||
        sc.size.height != static_cast<unsigned>(o.height))
      throw ConfigError(
          fmt::format("libcamera camera '{}' cannot give {} {}x{} (it would give "
                      "{}); sizes for {}: {}",
                      info_.camera_id, choice.format.toString(), o.width, o.height, sc.toString(),
                      choice.format.toString(), sc.formats().range(choice.format).toString()));
    if (const int ret = camera_->configure(config.get()); ret < 0)
      throw DeviceError(
          fmt::format("libcamera camera '{}': configure failed (error {})", info_.camera_id, ret));
    stream_ = sc.stream();
    info_.format = sc.pixelFormat.toString();
    info_.width = static_cast<int>(sc.size.width);
    info_.height = static_cast<int>(sc.size.height);
    info_.pixel = stream_pixel_format(sc);
    info_.exposure_time = offers(*camera_, lc::controls::ExposureTime);
    info_.analogue_gain = offers(*camera_, lc::controls::AnalogueGain);
    info_.ae_enable = offers(*camera_, lc::controls::AeEnable);

    allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
    if (const int ret = allocator_->allocate(stream_); ret < 0)
      throw DeviceError(fmt::format("libcamera camera '{}': buffer allocation failed (error {})",
                                    info_.camera_id, ret));
    const std::size_t need = v4l2::frame_bytes(info_.pixel, info_.height);
    for (const auto& buffer : allocator_->buffers(stream_)) {
      const lc::FrameBuffer::Plane& plane = buffer->planes().front();
      Mapping& m = mappings_.emplace_back();
      m.length = plane.offset + plane.length;
      m.base = mmap(nullptr, m.length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
      if (m.base == MAP_FAILED)
        throw DeviceError(
            fmt::format("libcamera camera '{}': mmap of a frame buffer failed", info_.camera_id));
      if (plane.length < need)
        throw ConfigError(
            fmt::format("libcamera camera '{}': a {} byte buffer for a {} byte "
                        "frame",
                        info_.camera_id, plane.length, need));
      m.bytes = {static_cast<const std::uint8_t*>(m.base) + plane.offset, plane.length};
      auto request = camera_->createRequest(requests_.size());
      if (!request || request->addBuffer(stream_, buffer.get()) < 0)
        throw DeviceError(
            fmt::format("libcamera camera '{}': cannot make a request", info_.camera_id));
      requests_.push_back(std::move(request));
    }
    queued_.resize(requests_.size());

    // The bracket sequencer owns exposure: auto exposure off from the first frame.
    lc::ControlList start_controls(camera_->controls());
    if (info_.ae_enable) start_controls.set(lc::controls::AeEnable, false);
    if (const int ret = camera_->start(&start_controls); ret < 0)
      throw DeviceError(
          fmt::format("libcamera camera '{}': start failed (error {})", info_.camera_id, ret));
    started_ = true;
    for (std::size_t i = 0; i < requests_.size(); ++i) queue(i, initial);
  } catch (...) {
    teardown();  // handles every partial state
    throw;
  }
}

LibcameraCamera::~LibcameraCamera() {
  teardown();
}

void LibcameraCamera::teardown() {
  if (!camera_) return;
  if (nodes_vanished_) return abandon();
  if (started_) camera_->stop();  // completes what is in flight as cancelled
  started_ = false;
  camera_->requestCompleted.disconnect(this);
  camera_->disconnected.disconnect(this);
  {
    std::lock_guard lock(mutex_);
    completed_.clear();
  }
  requests_.clear();
  for (Mapping& m : mappings_)
    if (m.base != MAP_FAILED) munmap(m.base, m.length);
  mappings_.clear();
  if (allocator_ && stream_) allocator_->free(stream_);
  allocator_.reset();
  if (acquired_) camera_->release();
  acquired_ = false;
  camera_.reset();
}

void LibcameraCamera::find_video_nodes() {
  // The capture nodes libcamera maps to this camera (CameraManager::get(dev_t)), to notice
  // them vanish: 0.0.3 emits Camera::disconnected only for pipelines with hotplug (UVC), not
  // for vimc or CSI pipelines whose driver is unbound or removed.
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/sys/class/video4linux", ec)) {
    const std::string dev = read_line(entry.path() / "dev");
    unsigned major = 0, minor = 0;
    if (std::sscanf(dev.c_str(), "%u:%u", &major, &minor) != 2) continue;
    if (manager_->get(makedev(major, minor)) == camera_)
      video_nodes_.push_back({entry.path() / "dev", dev});
  }
}

bool LibcameraCamera::video_nodes_gone() const {
  return std::any_of(video_nodes_.begin(), video_nodes_.end(),
                     [](const VideoNode& n) { return read_line(n.sysfs_dev) != n.dev; });
}

void LibcameraCamera::abandon() {
  // libcamera 0.0.3 cannot stop a camera whose nodes vanished without a disconnect:
  // Camera::stop() fails STREAMOFF, keeps the requests queued and aborts the process on
  // PipelineHandler::stop's assertion, and release() refuses a running camera. The pipeline
  // still points at our requests, so they, the buffers and the camera stay alive (a few
  // frame buffers per unplug), and this camera id is "gone" until the process restarts.
  camera_->requestCompleted.disconnect(this);
  camera_->disconnected.disconnect(this);
  for (Mapping& m : mappings_)
    if (m.base != MAP_FAILED) munmap(m.base, m.length);
  mappings_.clear();
  std::lock_guard lock(abandoned_mutex);
  abandoned().push_back({std::move(camera_), std::move(allocator_), std::move(requests_)});
}

void LibcameraCamera::on_request_completed(lc::Request* request) {
  {
    std::lock_guard lock(mutex_);
    completed_.push_back(request);
  }
  wake_.notify_one();
}

void LibcameraCamera::on_disconnected() {
  disconnected_ = true;
  wake_.notify_one();
}

void LibcameraCamera::queue(std::size_t index, const ExposureStamp& stamp) {
  const Exposure& exposure = stamp.exposure;
  lc::Request* request = requests_[index].get();
  request->reuse(lc::Request::ReuseBuffers);
  lc::ControlList& controls = request->controls();
  ExposureStamp asked = stamp;
  if (info_.ae_enable) controls.set(lc::controls::AeEnable, false);
  const lc::ControlInfoMap& infos = camera_->controls();
  if (info_.exposure_time) {
    const lc::ControlInfo& range = infos.find(&lc::controls::ExposureTime)->second;
    auto us = static_cast<std::int32_t>(std::lround(exposure.time_s * 1e6));
    if (range.min().type() == lc::ControlTypeInteger32 &&
        range.max().type() == lc::ControlTypeInteger32)
      us = std::clamp(us, range.min().get<std::int32_t>(), range.max().get<std::int32_t>());
    controls.set(lc::controls::ExposureTime, us);
    asked.exposure.time_s = us * 1e-6;
  }
  if (info_.analogue_gain) {
    const lc::ControlInfo& range = infos.find(&lc::controls::AnalogueGain)->second;
    auto gain = static_cast<float>(exposure.gain());
    if (range.min().type() == lc::ControlTypeFloat && range.max().type() == lc::ControlTypeFloat)
      gain = std::clamp(gain, range.min().get<float>(), range.max().get<float>());
    controls.set(lc::controls::AnalogueGain, gain);
    asked.exposure.gain_db = gain_db_from_linear(std::max(gain, 1e-3f));
  }
  queued_[index] = asked;
  if (const int ret = camera_->queueRequest(request); ret < 0)
    throw DeviceError(
        fmt::format("libcamera camera '{}': queueRequest failed (error {})", info_.camera_id, ret));
}

bool LibcameraCamera::next_frame(std::chrono::milliseconds timeout, const ExposureStamp& next,
                                 const std::function<void(const CompletedFrame&)>& use) {
  lc::Request* request = nullptr;
  {
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, timeout, [&] { return !completed_.empty() || disconnected_.load(); });
    if (disconnected_)
      throw DeviceError(fmt::format("libcamera camera '{}' disconnected", info_.camera_id));
    if (completed_.empty()) {
      lock.unlock();
      if (video_nodes_gone()) {
        nodes_vanished_ = true;
        throw DeviceError(fmt::format("libcamera camera '{}' is gone: its video nodes vanished",
                                      info_.camera_id));
      }
      return false;
    }
    request = completed_.front();
    completed_.pop_front();
  }
  const std::size_t index = request->cookie();
  const lc::FrameBuffer* buffer = request->findBuffer(stream_);
  const bool ok = request->status() == lc::Request::RequestComplete && buffer &&
                  buffer->metadata().status == lc::FrameMetadata::FrameSuccess;
  if (ok) {
    CompletedFrame frame;
    frame.bytes = mappings_[index].bytes;
    frame.queued = queued_[index];
    frame.sequence = buffer->metadata().sequence;
    const lc::ControlList& metadata = request->metadata();
    frame.timestamp_ns = static_cast<TimestampNs>(
        metadata.get(lc::controls::SensorTimestamp).value_or(buffer->metadata().timestamp));
    frame.exposure_us = metadata.get(lc::controls::ExposureTime);
    frame.analogue_gain = metadata.get(lc::controls::AnalogueGain);
    try {
      use(frame);
    } catch (...) {
      queue(index, next);  // keep the request in flight
      throw;
    }
  }
  queue(index, next);
  return ok;
}

}  // namespace probeless::libcam

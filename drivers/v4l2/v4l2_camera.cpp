#include "drivers/v4l2/v4l2_camera.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "drivers/v4l2/v4l2_format_map.hpp"

namespace probeless::v4l2 {
namespace {

[[noreturn]] void fail(const std::string& path, const char* what) {
  const int err = errno;
  throw DeviceError(path + ": " + errno_text(what, err), err);
}

std::string text(const __u8* chars, std::size_t n) {
  return std::string(reinterpret_cast<const char*>(chars),
                     strnlen(reinterpret_cast<const char*>(chars), n));
}

// A capture node's QUERYCAP, or nothing when it is not one (or cannot be opened).
UniqueFd open_capture(const std::string& path, v4l2_capability& cap) {
  // Non-blocking: DQBUF must never wait (poll() does the waiting, with the read timeout).
  UniqueFd fd(::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC));
  if (!fd) return fd;
  std::memset(&cap, 0, sizeof cap);
  if (xioctl(fd.get(), VIDIOC_QUERYCAP, &cap) != 0) return UniqueFd();
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    errno = ENOTTY;
    return UniqueFd();
  }
  return fd;
}

}  // namespace

V4l2Camera::V4l2Camera(const V4l2Options& options) {
  open_device(options);
  negotiate_format(options);
  set_frame_interval(options.fps);
  info_.exposure = query_control(V4L2_CID_EXPOSURE_ABSOLUTE);
  info_.gain = query_control(V4L2_CID_GAIN);
  take_manual_control();
  start_streaming(options.buffers);
}

V4l2Camera::~V4l2Camera() {
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_.get(), VIDIOC_STREAMOFF, &type);  // fails harmlessly on a vanished device
  }
  buffers_.clear();  // unmap before the descriptor closes
}

void V4l2Camera::open_device(const V4l2Options& options) {
  v4l2_capability cap{};
  if (options.device.front() == '/') {
    info_.path = options.device;
    fd_ = open_capture(info_.path, cap);
    if (!fd_) fail(info_.path, "open as a V4L2 capture device");
  } else {
    // By card name: the node number can change when the device comes back.
    std::vector<std::string> nodes;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/dev", ec)) {
      const std::string name = e.path().filename().string();
      if (name.starts_with("video")) nodes.push_back(e.path().string());
    }
    std::sort(nodes.begin(), nodes.end());
    for (const auto& node : nodes) {
      UniqueFd fd = open_capture(node, cap);
      if (fd && text(cap.card, sizeof cap.card).starts_with(options.device)) {
        info_.path = node;
        fd_ = std::move(fd);
        break;
      }
    }
    if (!fd_)
      throw DeviceError("no V4L2 capture device with card '" + options.device + "'", ENODEV);
  }
  info_.card = text(cap.card, sizeof cap.card);
  info_.driver = text(cap.driver, sizeof cap.driver);
  info_.bus_info = text(cap.bus_info, sizeof cap.bus_info);
}

void V4l2Camera::negotiate_format(const V4l2Options& options) {
  std::vector<std::pair<std::uint32_t, PixelFormat>> offered;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd_.get(), VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    if (auto f = layout_of(desc.pixelformat)) offered.emplace_back(desc.pixelformat, *f);
  }
  if (errno != EINVAL) fail(info_.path, "VIDIOC_ENUM_FMT");
  if (!options.format.empty()) {
    const std::uint32_t want = fourcc_from_text(options.format);
    std::erase_if(offered, [&](const auto& o) { return o.first != want; });
    if (offered.empty())
      throw ConfigError(info_.path + ": does not offer format " + options.format +
                        " (or it is not one probeless converts: docs/drivers.md)");
  }
  if (offered.empty())
    throw ConfigError(info_.path + ": offers no raw Bayer, RGB24 or YUYV format");
  std::stable_sort(offered.begin(), offered.end(), [](const auto& a, const auto& b) {
    return preference(a.second) < preference(b.second);
  });
  // The best format that takes the configured size as it is: the calibration is for that
  // size, so a driver's "nearest" size would be wrong, not close.
  std::string tried;
  for (auto& [fourcc, pixel] : offered) {
    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.width = static_cast<__u32>(options.width);
    fmt.fmt.pix.height = static_cast<__u32>(options.height);
    fmt.fmt.pix.pixelformat = fourcc;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(fd_.get(), VIDIOC_S_FMT, &fmt) != 0) fail(info_.path, "VIDIOC_S_FMT");
    const auto& pix = fmt.fmt.pix;
    if (pix.pixelformat == fourcc && static_cast<int>(pix.width) == options.width &&
        static_cast<int>(pix.height) == options.height && pix.field == V4L2_FIELD_NONE) {
      apply_colourimetry(pix, pixel);
      info_.pixel = pixel;
      info_.fourcc = fourcc_text(fourcc);
      info_.width = options.width;
      info_.height = options.height;
      return;
    }
    tried += fmt::format(" {}->{}x{}", fourcc_text(fourcc), pix.width, pix.height);
  }
  throw ConfigError(fmt::format("{}: no format gives {}x{} progressive (driver offered:{})",
                                info_.path, options.width, options.height, tried));
}

void V4l2Camera::set_frame_interval(double fps) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  info_.fps = fps;
  if (xioctl(fd_.get(), VIDIOC_G_PARM, &parm) != 0 ||
      !(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
    spdlog::warn("{}: no frame interval control; assuming {} fps", info_.path, fps);
    return;
  }
  parm.parm.capture.timeperframe.numerator = 1000;
  parm.parm.capture.timeperframe.denominator = static_cast<__u32>(std::lround(fps * 1000));
  if (xioctl(fd_.get(), VIDIOC_S_PARM, &parm) != 0) fail(info_.path, "VIDIOC_S_PARM");
  const auto& tpf = parm.parm.capture.timeperframe;  // what the driver chose
  if (tpf.numerator != 0 && tpf.denominator != 0) {
    info_.fps = static_cast<double>(tpf.denominator) / tpf.numerator;
    info_.fps_from_device = true;
  }
  if (std::abs(info_.fps - fps) > 0.01 * fps)
    spdlog::warn("{}: asked for {} fps, the driver runs at {:.3f}", info_.path, fps, info_.fps);
}

ControlRange V4l2Camera::query_control(std::uint32_t id) const {
  v4l2_queryctrl q{};
  q.id = id;
  ControlRange r;
  if (xioctl(fd_.get(), VIDIOC_QUERYCTRL, &q) != 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) return r;
  r.present = !(q.flags & V4L2_CTRL_FLAG_READ_ONLY);
  r.min = q.minimum;
  r.max = q.maximum;
  r.step = std::max(1, q.step);
  r.def = q.default_value;
  return r;
}

void V4l2Camera::take_manual_control() {
  // The bracket sequencer owns exposure and gain; a camera's own loop would fight it.
  auto set = [&](std::uint32_t id, std::int32_t value, const char* name) {
    if (!query_control(id).present) return;
    v4l2_control c{id, value};
    if (xioctl(fd_.get(), VIDIOC_S_CTRL, &c) != 0)
      spdlog::warn("{}: could not set {}: {}", info_.path, name, std::strerror(errno));
  };
  set(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "exposure_auto=manual");
  set(V4L2_CID_AUTOGAIN, 0, "autogain=0");
}

void V4l2Camera::start_streaming(int buffers) {
  v4l2_requestbuffers req{};
  req.count = static_cast<__u32>(buffers);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_.get(), VIDIOC_REQBUFS, &req) != 0) fail(info_.path, "VIDIOC_REQBUFS");
  if (req.count < 2)
    throw DeviceError(info_.path + ": the driver gave fewer than 2 buffers", ENOMEM);
  const std::size_t need = frame_bytes(info_.pixel, info_.height);
  for (__u32 i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (xioctl(fd_.get(), VIDIOC_QUERYBUF, &b) != 0) fail(info_.path, "VIDIOC_QUERYBUF");
    if (b.length < need) throw ConfigError(info_.path + ": buffer smaller than a frame");
    buffers_.emplace_back(fd_.get(), b.length, static_cast<long>(b.m.offset));
    if (xioctl(fd_.get(), VIDIOC_QBUF, &b) != 0) fail(info_.path, "VIDIOC_QBUF");
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_.get(), VIDIOC_STREAMON, &type) != 0) fail(info_.path, "VIDIOC_STREAMON");
  streaming_ = true;
}

bool V4l2Camera::next_frame(std::chrono::milliseconds timeout, const Consumer& consume) {
  pollfd p{fd_.get(), POLLIN, 0};
  int r = 0;
  do {
    r = ::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(0, timeout.count())));
  } while (r < 0 && errno == EINTR);  // a signal shortens this wait; the caller reads again
  if (r < 0) fail(info_.path, "poll");
  if (r == 0) return false;
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_.get(), VIDIOC_DQBUF, &b) != 0) {
    if (errno == EAGAIN) return false;
    fail(info_.path, "VIDIOC_DQBUF");
  }
  TimestampNs t = 0;
  if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
    t = static_cast<TimestampNs>(b.timestamp.tv_sec) * 1'000'000'000 +
        static_cast<TimestampNs>(b.timestamp.tv_usec) * 1'000;
  } else {
    t = monotonic_now_ns();  // the driver's clock is unknown: the dequeue time is the best
  }
  const bool good = !(b.flags & V4L2_BUF_FLAG_ERROR) && b.index < buffers_.size() &&
                    b.bytesused >= frame_bytes(info_.pixel, info_.height);
  if (good) consume({buffers_[b.index].data(), b.bytesused}, t, b.sequence);
  if (xioctl(fd_.get(), VIDIOC_QBUF, &b) != 0) fail(info_.path, "VIDIOC_QBUF");
  return good;
}

AppliedControls V4l2Camera::set_controls(std::optional<std::int64_t> exposure,
                                         std::optional<std::int64_t> gain) {
  std::vector<v4l2_ext_control> cs;
  auto add = [&](std::uint32_t id, const ControlRange& range, std::optional<std::int64_t> v) {
    if (!range.present || !v) return;
    std::int64_t value = std::clamp(*v, range.min, range.max);
    value = range.min + (value - range.min) / range.step * range.step;
    v4l2_ext_control c{};
    c.id = id;
    c.value = static_cast<std::int32_t>(value);
    cs.push_back(c);
  };
  add(V4L2_CID_EXPOSURE_ABSOLUTE, info_.exposure, exposure);
  add(V4L2_CID_GAIN, info_.gain, gain);
  AppliedControls applied;
  if (cs.empty()) return applied;
  v4l2_ext_controls ext{};
  ext.which = V4L2_CTRL_WHICH_CUR_VAL;  // lets one call mix the camera and user classes
  ext.count = static_cast<__u32>(cs.size());
  ext.controls = cs.data();
  if (xioctl(fd_.get(), VIDIOC_S_EXT_CTRLS, &ext) != 0) fail(info_.path, "VIDIOC_S_EXT_CTRLS");
  // Read back: the driver may have rounded, and the frame is stamped with what it applied.
  if (xioctl(fd_.get(), VIDIOC_G_EXT_CTRLS, &ext) != 0) fail(info_.path, "VIDIOC_G_EXT_CTRLS");
  for (const auto& c : cs) {
    if (c.id == V4L2_CID_EXPOSURE_ABSOLUTE) applied.exposure = c.value;
    if (c.id == V4L2_CID_GAIN) applied.gain = c.value;
  }
  return applied;
}

}  // namespace probeless::v4l2

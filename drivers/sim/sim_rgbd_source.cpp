#include <algorithm>
#include <array>
#include <cmath>
#include <thread>

#include "core/capture_stamp.hpp"
#include "core/depth_noise.hpp"
#include "drivers/sim/sim_random.hpp"
#include "drivers/sim/sim_sources.hpp"

namespace probeless::sim {

namespace {

// Auto exposure: the log-mean (geometric mean) of the scene maps to 0.18, white balance is
// the grey world in the log domain (the window's blue sky does not swamp it); both follow
// an exponential average over the last kMeterFrames frames, so they lag a few frames as a
// real camera's do. Metering looks at a kMeterScale-times smaller image.
constexpr int kMeterFrames = 8;
constexpr double kMeterSmoothing = 0.35;
constexpr int kMeterScale = 8;
constexpr double kMidGrey = 0.18;
// Colour sensor noise in linear units of full scale: shot (variance proportional to the
// signal) and read noise.
constexpr float kShotNoise = 1e-4f;
constexpr float kReadNoise = 4e-4f;

// Linear [0, 1] in 1/65535 steps -> 8-bit with gamma 2.2.
const std::array<std::uint8_t, 65536>& gamma_table() {
  static const auto table = [] {
    std::array<std::uint8_t, 65536> t{};
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<std::uint8_t>(std::lround(255.0 * std::pow(i / 65535.0, 1.0 / 2.2)));
    return t;
  }();
  return table;
}

}  // namespace

std::int64_t FramePacer::latest_due(TimestampNs now) const {
  return static_cast<std::int64_t>(std::floor((now - start_ns_) * 1e-9 * fps_));
}

bool FramePacer::wait_until(TimestampNs deadline, std::chrono::milliseconds timeout) {
  const TimestampNs now = monotonic_now_ns();
  if (deadline <= now) return true;
  const TimestampNs limit =
      now + std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
  std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(deadline, limit) - now));
  return deadline <= limit;
}

SimRgbdSource::SimRgbdSource(std::shared_ptr<const SimWorld> world, const SimOptions& options,
                             const RigGeometry& geometry, TimestampNs start_ns)
    : world_(std::move(world)),
      options_(options),
      geometry_(geometry),
      pacer_(start_ns, options.rgbd_fps, options.realtime, options.start_s),
      pool_(options.render_threads),
      renderer_(world_, geometry.width, geometry.height, geometry.fx, geometry.fy, geometry.cx,
                geometry.cy, &pool_),
      meter_renderer_(world_, geometry.width / kMeterScale, geometry.height / kMeterScale,
                      geometry.fx / kMeterScale, geometry.fy / kMeterScale,
                      (geometry.cx + 0.5) / kMeterScale - 0.5,
                      (geometry.cy + 0.5) / kMeterScale - 0.5, nullptr) {
  renderer_.set_edge_samples(options.edge_samples);
}

ReadResult SimRgbdSource::read(RgbdFrame& frame, std::chrono::milliseconds timeout) {
  for (;;) {
    if (options_.max_frames >= 0 && next_ >= options_.max_frames) {
      state_ = SourceState::Ended;
      return ReadResult::EndOfStream;
    }
    // With stall_every, the stall [begin, end) repeats every stall_every frames (a replug).
    std::int64_t stall_begin = options_.stall_begin, stall_end = options_.stall_end;
    if (options_.stall_every > 0 && next_ >= stall_begin) {
      const std::int64_t shift =
          (next_ - stall_begin) / options_.stall_every * options_.stall_every;
      stall_begin += shift;
      stall_end += shift;
    }
    if (next_ >= stall_begin && next_ < stall_end) {
      // A stall lasts as long as its frames would have, in wall-clock time, in both modes.
      state_ = SourceState::NoSignal;
      TimestampNs end = pacer_.timestamp(stall_end);
      if (!pacer_.realtime()) {
        if (stall_wall_end_ == 0)
          stall_wall_end_ =
              monotonic_now_ns() + pacer_.timestamp(stall_end) - pacer_.timestamp(next_);
        end = stall_wall_end_;
      }
      if (!FramePacer::wait_until(end, timeout)) return ReadResult::NoFrameYet;
      next_ = stall_end;
      stall_wall_end_ = 0;
      continue;
    }
    if (pacer_.realtime()) {
      if (!FramePacer::wait_until(pacer_.timestamp(next_), timeout)) return ReadResult::NoFrameYet;
      // A slow reader misses frames, as with a camera; it never gets old ones.
      const std::int64_t latest = pacer_.latest_due(monotonic_now_ns());
      if (latest > next_) {
        next_ = latest;
        continue;  // the newest frame may lie in a stall or past the end
      }
    }
    break;
  }
  if (next_ < static_cast<std::int64_t>(prerendered_.size())) {
    // Moved out: each is read once (next_ only grows), and copying 1.5 MB a frame was the
    // sim's RGB-D thread's whole cost in `bench pipeline --prerender` (perf, 2026-11-28).
    frame = std::move(prerendered_[static_cast<std::size_t>(next_)]);
    // The clock restarted after the rendering; or when read, as a camera delivers.
    frame.timestamp_ns = options_.stamp_on_read ? std::max(monotonic_now_ns(), last_stamp_ns_ + 1)
                                                : pacer_.timestamp(next_);
    last_stamp_ns_ = frame.timestamp_ns;
  } else {
    render_frame(next_, frame);
  }
  // After the timestamp is final (a prerendered frame gets its own here).
  if (options_.stamp) draw_capture_stamp(frame.colour, frame.timestamp_ns);
  ++next_;
  state_ = SourceState::Streaming;
  return ReadResult::Frame;
}

void SimRgbdSource::prerender(std::int64_t count) {
  if (options_.max_frames >= 0) count = std::min(count, options_.max_frames);
  prerendered_.resize(static_cast<std::size_t>(std::max<std::int64_t>(count, 0)));
  for (std::size_t i = 0; i < prerendered_.size(); ++i)
    render_frame(static_cast<std::int64_t>(i), prerendered_[i]);
}

const SimRgbdSource::Metering& SimRgbdSource::meter(std::int64_t index) {
  index = std::max<std::int64_t>(index, 0);
  if (auto it = metering_.find(index); it != metering_.end()) return it->second;
  const double t = pacer_.seconds(index);
  const Pose rig = world_->rig_pose(options_.trajectory, t);
  const Pose camera = rig * geometry_.T_rig_rgb;
  const Occluder arm = scene_occluders(*world_, options_, t, camera);
  meter_renderer_.render(camera, SimWorld::lamp_state(t), arm_in_view(options_, arm), false);
  const ImageRGBF& rad = meter_renderer_.radiance();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < rad.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) sum[c] += std::log(1e-3 + rad.data()[3 * i + c]);
  Metering m{sum / static_cast<double>(rad.pixel_count())};
  // Keep only what the next frames can still ask for.
  while (!metering_.empty() && metering_.begin()->first < index - 2 * kMeterFrames)
    metering_.erase(metering_.begin());
  return metering_.emplace(index, m).first->second;
}

void SimRgbdSource::auto_exposure(std::int64_t index, double& gain,
                                  Eigen::Vector3d& white_balance) {
  Eigen::Vector3d log_mean = Eigen::Vector3d::Zero();
  double weight_sum = 0, weight = 1;
  for (int k = 1; k <= kMeterFrames; ++k) {
    log_mean += weight * meter(index - k).log_mean;
    weight_sum += weight;
    weight *= 1 - kMeterSmoothing;
  }
  log_mean /= weight_sum;
  const double log_y = 0.2126 * log_mean[0] + 0.7152 * log_mean[1] + 0.0722 * log_mean[2];
  gain = kMidGrey / std::exp(log_y);
  for (int c = 0; c < 3; ++c)
    white_balance[c] = std::clamp(std::exp(log_y - log_mean[c]), 0.5, 2.0);
}

void SimRgbdSource::render_frame(std::int64_t index, RgbdFrame& frame) {
  const double t = pacer_.seconds(index);
  const Pose rig = world_->rig_pose(options_.trajectory, t);
  const Pose camera = rig * geometry_.T_rig_rgb;
  const int lamps = SimWorld::lamp_state(t);
  const Occluder arm = scene_occluders(*world_, options_, t, camera);
  renderer_.render(camera, lamps, arm_in_view(options_, arm), true);

  double gain;
  Eigen::Vector3d wb;
  auto_exposure(index, gain, wb);
  const int w = geometry_.width, h = geometry_.height;
  const ImageF& depth_m = renderer_.depth();
  const ImageGray8& flags = renderer_.flags();
  const auto to_mm = [](float z) {
    // Depths are positive: + 0.5 and truncation rounds (std::lround is a library call).
    return static_cast<std::uint16_t>(std::min(z * 1000.0f + 0.5f, 65535.0f));
  };
  DepthImage clean(w, h), measurable(w, h);
  for (std::size_t i = 0; i < clean.pixel_count(); ++i) {
    const std::uint16_t mm = to_mm(depth_m.data()[i]);
    clean.data()[i] = mm;
    measurable.data()[i] = (flags.data()[i] & kFlagNoDepth) ? 0 : mm;
  }

  frame.sequence = static_cast<std::uint64_t>(index);
  frame.timestamp_ns = pacer_.timestamp(index);
  if (frame.colour.width() != w || frame.colour.height() != h) frame.colour = ImageRGB8(w, h);
  const std::uint64_t frame_seed = hash_combine(world_->seed(), static_cast<std::uint64_t>(index));
  const auto key = static_cast<std::uint32_t>(frame_seed);
  const auto& lut = gamma_table();
  const ImageRGBF& rad = renderer_.radiance();
  std::vector<float> scale(3 * static_cast<std::size_t>(w));  // per element of a row
  for (std::size_t i = 0; i < scale.size(); ++i)
    scale[i] = static_cast<float>(gain * wb[static_cast<int>(i % 3)]);
  constexpr int kRowsPerTask = 48;
  const int colour_tasks = (h + kRowsPerTask - 1) / kRowsPerTask;
  // The depth noise runs beside the colour conversion (one task against many small ones).
  pool_.parallel_for(1 + colour_tasks, [&](int task) {
    if (task == 0) {
      frame.depth = apply_kinect_noise(measurable, geometry_.fx, hash_combine(frame_seed, 1));
      return;
    }
    const int n = 3 * w;
    Eigen::ArrayXf noise(n), v(n);
    std::vector<std::int32_t> level(n);
    const Eigen::Map<const Eigen::ArrayXf> scale_row(scale.data(), n);
    const int y0 = (task - 1) * kRowsPerTask, y1 = std::min(h, y0 + kRowsPerTask);
    for (int y = y0; y < y1; ++y) {
      // Whole-row passes that vectorise: std::sqrt in a scalar loop does not (errno), nor
      // Eigen's cast<int>; a plain float -> int32 loop does (measured: 3.3 -> 1.9 ms a frame).
      fill_unit_noise(noise.data(), n, key, static_cast<std::uint32_t>(y) * n);
      v = Eigen::Map<const Eigen::ArrayXf>(rad.row(y), n) * scale_row;
      v += (kShotNoise * v.max(0.0f) + kReadNoise * kReadNoise).sqrt() * noise;
      v = v.max(0.0f).min(1.0f) * 65535.0f + 0.5f;
      for (int i = 0; i < n; ++i) level[i] = static_cast<std::int32_t>(v[i]);
      std::uint8_t* out = frame.colour.row(y);
      for (int i = 0; i < n; ++i) out[i] = lut[level[i]];
    }
  });

  if (options_.ground_truth) {
    auto truth = std::make_shared<FrameTruth>();
    truth->clean_depth = std::move(clean);
    truth->occluder_mask = ImageGray8(w, h);
    for (std::size_t i = 0; i < flags.pixel_count(); ++i)
      truth->occluder_mask.data()[i] = (flags.data()[i] & kFlagOccluder) ? 255 : 0;
    truth->rig_pose = rig;
    truth->light = world_->light(lamps);
    // Each layer alone through the camera's gain, white balance and gamma, without noise.
    const auto encode = [&](const Eigen::Vector3f& radiance) {
      std::array<std::uint8_t, 3> rgb{};
      for (int c = 0; c < 3; ++c) {
        const float v = std::clamp(radiance[c] * scale[static_cast<std::size_t>(c)], 0.0f, 1.0f);
        rgb[static_cast<std::size_t>(c)] = lut[static_cast<std::size_t>(v * 65535.0f + 0.5f)];
      }
      return rgb;
    };
    truth->mixed_pixels.reserve(renderer_.edge_pixels().size());
    for (const EdgePixel& e : renderer_.edge_pixels())
      truth->mixed_pixels.push_back({static_cast<std::uint32_t>(e.index), e.near_coverage,
                                     to_mm(e.near_depth), to_mm(e.far_depth),
                                     encode(e.near_radiance), encode(e.far_radiance)});
    frame.truth = std::move(truth);
  } else {
    frame.truth.reset();
  }
}

}  // namespace probeless::sim

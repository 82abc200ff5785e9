#include <algorithm>
#include <cmath>

#include "drivers/sim/sim_random.hpp"
#include "drivers/sim/sim_sources.hpp"

namespace probeless::sim {

namespace {

// A linear raw sensor (docs/sim.md "The fisheye"). At 12 bit: black level 256, and full scale
// (4095 - 256 DN at unit gain) holds 10000 electrons. Sensitivity: DN above black per unit
// scene radiance per second of exposure at 0 dB, chosen so that a lamp-lit wall reads about a
// third of full scale at 10 ms and the window needs about 1/50 of that exposure.
struct SensorModel {
  double black;
  double white;
  double dn_per_electron;  // at unit gain
  double sensitivity;
  double read_noise_e = 3.0;
  double adc_noise_dn;
};

SensorModel sensor_model(int bit_depth) {
  const double full_scale_12 = 4095.0 - 256.0;
  SensorModel m{256.0, 4095.0, full_scale_12 / 10000.0, 600.0, 3.0, 0.5};
  if (bit_depth == 8) {
    const double k = (255.0 - 16.0) / full_scale_12;
    m = {16.0, 255.0, m.dn_per_electron * k, m.sensitivity * k, 3.0, 0.3};
  }
  return m;
}

}  // namespace

SimFisheyeSource::SimFisheyeSource(std::shared_ptr<const SimWorld> world, const SimOptions& options,
                                   const RigGeometry& geometry,
                                   std::shared_ptr<const CameraModel> camera, TimestampNs start_ns)
    : world_(std::move(world)),
      options_(options),
      geometry_(geometry),
      pacer_(start_ns, options.fisheye_fps, options.fisheye_realtime.value_or(options.realtime),
             options.start_s),
      pool_(options.render_threads),
      renderer_(world_, *camera, &pool_),
      end_index_(options.max_frames < 0
                     ? -1
                     : static_cast<std::int64_t>(std::floor(
                           options.max_frames * options.fisheye_fps / options.rgbd_fps))) {}

void SimFisheyeSource::set_next_exposure(const ExposureStamp& exposure) {
  std::lock_guard lock(exposure_mutex_);
  exposure_ = exposure;
}

ReadResult SimFisheyeSource::read(FisheyeFrame& frame, std::chrono::milliseconds timeout) {
  for (;;) {
    if (end_index_ >= 0 && next_ >= end_index_) {
      state_ = SourceState::Ended;
      return ReadResult::EndOfStream;
    }
    if (!pacer_.realtime()) break;
    if (!FramePacer::wait_until(pacer_.timestamp(next_), timeout)) return ReadResult::NoFrameYet;
    const std::int64_t latest = pacer_.latest_due(monotonic_now_ns());
    if (latest <= next_) break;
    next_ = latest;
  }
  ExposureStamp exposure;
  {
    std::lock_guard lock(exposure_mutex_);
    exposure = exposure_;
  }
  const auto count = static_cast<std::int64_t>(prerendered_.size());
  if (options_.fisheye_repeat && options_.fisheye_scenes > 0 && count > 0) {
    const std::int64_t index = next_ % count;
    const Scene& scene = prerendered_[static_cast<std::size_t>(index)];
    const auto key = std::make_tuple(index, exposure.exposure.time_s, exposure.exposure.gain_db);
    if (const auto it = kept_.find(key); it != kept_.end()) {
      frame.raw = it->second;
      stamp(next_, scene.truth, exposure, frame);
    } else {
      expose(next_, scene.radiance, scene.truth, exposure, frame);
      if (kept_.size() >= kMaxKept) kept_.clear();
      kept_.emplace(key, frame.raw);
    }
  } else if (next_ < count || (options_.fisheye_repeat && count > 0)) {
    const Scene& scene = prerendered_[static_cast<std::size_t>(next_ % count)];
    expose(next_, scene.radiance, scene.truth, exposure, frame);
  } else {
    render_frame(next_, exposure, frame);
  }
  ++next_;
  state_ = SourceState::Streaming;
  return ReadResult::Frame;
}

void SimFisheyeSource::prerender(std::int64_t count) {
  if (end_index_ >= 0) count = std::min(count, end_index_);
  prerendered_.resize(static_cast<std::size_t>(std::max<std::int64_t>(count, 0)));
  for (std::size_t i = 0; i < prerendered_.size(); ++i)
    render_scene(static_cast<std::int64_t>(i), prerendered_[i], true);
}

void SimFisheyeSource::render_frame(std::int64_t index, const ExposureStamp& exposure,
                                    FisheyeFrame& frame) {
  Scene live;
  render_scene(index, live, false);
  expose(index, renderer_.radiance(), live.truth, exposure, frame);
}

void SimFisheyeSource::render_scene(std::int64_t index, Scene& scene, bool keep_radiance) {
  const double t = pacer_.seconds(index);
  const Pose rig = world_->rig_pose(options_.trajectory, t);
  const int lamps = SimWorld::lamp_state(t);
  const Occluder arm = scene_occluders(*world_, options_, t, rig * geometry_.T_rig_rgb);
  renderer_.render(rig * geometry_.T_rig_fisheye, lamps, arm_in_view(options_, arm), false);
  if (keep_radiance) scene.radiance = renderer_.radiance();
  if (options_.ground_truth) {
    auto truth = std::make_shared<FrameTruth>();
    truth->rig_pose = rig;
    truth->light = world_->light(lamps);
    scene.truth = std::move(truth);
  } else {
    scene.truth.reset();
  }
}

void SimFisheyeSource::expose(std::int64_t index, const ImageRGBF& rad,
                              const std::shared_ptr<const FrameTruth>& truth,
                              const ExposureStamp& exposure, FisheyeFrame& frame) {
  const SensorModel m = sensor_model(options_.fisheye_bit_depth);
  const double gain = exposure.exposure.gain();
  const auto to_dn = static_cast<float>(m.sensitivity * exposure.exposure.time_s * gain);
  const auto shot = static_cast<float>(m.dn_per_electron * gain);  // DN^2 per DN of signal
  const double read_dn = m.read_noise_e * m.dn_per_electron * gain;
  const auto read_var = static_cast<float>(read_dn * read_dn + m.adc_noise_dn * m.adc_noise_dn);
  const auto black = static_cast<float>(m.black), white = static_cast<float>(m.white);

  const int w = rad.width(), h = rad.height();
  if (frame.raw.width() != w || frame.raw.height() != h) frame.raw = ImageRGB16(w, h);
  const auto key = static_cast<std::uint32_t>(
      hash_combine(hash_combine(world_->seed(), 0xf15e7e), static_cast<std::uint64_t>(index)));
  constexpr int kRowsPerTask = 32;
  pool_.parallel_for((h + kRowsPerTask - 1) / kRowsPerTask, [&](int task) {
    const int n = 3 * w;
    Eigen::ArrayXf noise(n), signal(n);
    const int y1 = std::min(h, (task + 1) * kRowsPerTask);
    for (int y = task * kRowsPerTask; y < y1; ++y) {
      // Row passes that vectorise (see the RGB-D colour conversion).
      fill_unit_noise(noise.data(), n, key, static_cast<std::uint32_t>(y) * n);
      signal = Eigen::Map<const Eigen::ArrayXf>(rad.row(y), n) * to_dn;
      signal =
          (black + signal + (shot * signal + read_var).sqrt() * noise + 0.5f).max(0.0f).min(white);
      std::uint16_t* out = frame.raw.row(y);
      for (int i = 0; i < n; ++i)
        out[i] = static_cast<std::uint16_t>(static_cast<std::int32_t>(signal[i]));
    }
  });

  stamp(index, truth, exposure, frame);
}

void SimFisheyeSource::stamp(std::int64_t index, const std::shared_ptr<const FrameTruth>& truth,
                             const ExposureStamp& exposure, FisheyeFrame& frame) const {
  frame.sequence = static_cast<std::uint64_t>(index);
  frame.timestamp_ns = pacer_.timestamp(index);
  frame.bit_depth = options_.fisheye_bit_depth;
  frame.black_level = static_cast<std::uint16_t>(sensor_model(options_.fisheye_bit_depth).black);
  frame.exposure = exposure;
  frame.truth = truth;
}

}  // namespace probeless::sim

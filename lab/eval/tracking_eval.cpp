#include "lab/eval/tracking_eval.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "base/stage_stats.hpp"
#include "lab/eval/trajectory_metrics.hpp"

namespace probeless::eval {

std::optional<double> central_median_depth_m(const DepthImage& depth_mm, int window) {
  const int x0 = std::max(0, depth_mm.width() / 2 - window / 2);
  const int y0 = std::max(0, depth_mm.height() / 2 - window / 2);
  std::vector<double> valid;
  for (int y = y0; y < std::min(depth_mm.height(), y0 + window); ++y)
    for (int x = x0; x < std::min(depth_mm.width(), x0 + window); ++x)
      if (depth_mm.at(x, y) > 0) valid.push_back(depth_mm.at(x, y) * 1e-3);
  if (valid.empty()) return std::nullopt;
  return quantile(std::move(valid), 0.5);
}

TrackingEvalReport evaluate_tracking(TrackingSequence& sequence,
                                     const std::vector<std::string>& names,
                                     const TrackingDepthRange& range, ComputeContext* ctx) {
  struct Run {
    std::unique_ptr<TrackingMethod> method;
    std::vector<PosePair> poses;
    std::vector<TrackingStep> steps;
    std::vector<double> ms;
    int lost = 0;
  };
  std::vector<Run> runs;
  for (const auto& name : names)
    runs.push_back({make_tracking_method(name, sequence.camera(), range, ctx,
                                         sequence.rolling_shutter_readout_s()),
                    {},
                    {},
                    {},
                    0});

  TrackingEvalReport report;
  report.sequence = sequence.name();
  report.camera = sequence.camera_description();
  report.camera_intrinsics = sequence.camera();
  while (auto frame = sequence.next()) {
    if (report.frames == 0) {
      const auto d = central_median_depth_m(frame->depth_mm);
      if (!d)
        throw std::invalid_argument(
            "the first frame has no depth in its central 64x64 window: no anchor for the "
            "registration error");
      report.anchor_depth_m = *d;
    }
    for (auto& run : runs) {
      const auto t0 = std::chrono::steady_clock::now();
      const TrackingStep step =
          run.method->track(frame->colour, frame->depth_mm, frame->timestamp_ns);
      if (report.frames > 0) run.ms.push_back(ms_since(t0));
      run.lost += step.lost ? 1 : 0;
      run.poses.push_back({frame->timestamp_ns, step.T_world_camera, frame->T_world_camera});
      run.steps.push_back(step);
    }
    ++report.frames;
    if (report.frames % 100 == 0) spdlog::info("eval tracking: {} frames", report.frames);
  }
  if (report.frames == 0) throw std::invalid_argument(sequence.name() + ": no frames");

  const Eigen::Vector3d anchor(0, 0, report.anchor_depth_m);  // on the first optical axis
  for (auto& run : runs) {
    TrackingMethodReport m;
    m.name = run.method->name();
    m.ate_rmse_m = ate_rmse_m(run.poses);
    if (const auto rpe = relative_pose_error(run.poses, 1.0)) {
      m.rpe_t_m = rpe->translation_rmse_m;
      m.rpe_r_deg = rpe->rotation_rmse_deg;
      m.rpe_pairs = rpe->pairs;
    }
    const auto reg = registration_px(run.poses, sequence.camera(), anchor);
    m.reg_frames = static_cast<int>(reg.size());
    m.reg_px_p50 = quantile(reg, 0.5);
    m.reg_px_p95 = quantile(reg, 0.95);
    const TimingSummary t = summarize(run.ms);
    m.p50_ms = t.p50_ms;
    m.p99_ms = t.p99_ms;
    m.lost_frames = run.lost;
    m.poses = std::move(run.poses);
    m.steps = std::move(run.steps);
    report.methods.push_back(std::move(m));
  }
  return report;
}

void write_tum_trajectories(const TrackingEvalReport& report, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const auto line = [](TimestampNs t, const Pose& p) {
    const auto& q = p.rotation;
    return fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", t * 1e-9,
                       p.translation.x(), p.translation.y(), p.translation.z(), q.x(), q.y(), q.z(),
                       q.w());
  };
  const auto write = [&](const std::string& name, const std::vector<PosePair>& poses, bool truth) {
    const std::string path = (std::filesystem::path(dir) / (name + ".txt")).string();
    std::ofstream out(path);
    out << "# timestamp tx ty tz qx qy qz qw (" << report.sequence << ", " << name << ")\n";
    for (const auto& p : poses)
      if (!truth)
        out << line(p.timestamp_ns, p.estimate);
      else if (p.truth)
        out << line(p.timestamp_ns, *p.truth);
    if (!out) throw std::runtime_error("cannot write " + path);
  };
  for (const auto& m : report.methods) write(m.name, m.poses, false);
  if (!report.methods.empty()) write("groundtruth", report.methods.front().poses, true);
}

void write_per_frame_csv(const TrackingEvalReport& report, const std::string& path) {
  std::ofstream out(path);
  out << "frame,timestamp_s,method,lost,keyframe,reg_px,rotation_error_deg,translation_error_m\n";
  const Eigen::Vector3d anchor(0, 0, report.anchor_depth_m);
  for (const auto& m : report.methods) {
    const auto reg = registration_px_per_frame(m.poses, report.camera_intrinsics, anchor);
    const Pose est_first_inv = m.poses.front().estimate.inverse();
    const Pose truth_first_inv = m.poses.front().truth->inverse();
    for (std::size_t i = 0; i < m.poses.size(); ++i) {
      const PosePair& f = m.poses[i];
      std::string rotation, translation;
      if (f.truth) {
        // The relative poses' difference, in the camera's axes.
        const Pose e = (truth_first_inv * *f.truth).inverse() * (est_first_inv * f.estimate);
        rotation = fmt::format("{:.4f}", Eigen::AngleAxisd(e.rotation).angle() * 180.0 / M_PI);
        translation = fmt::format("{:.5f}", e.translation.norm());
      }
      out << fmt::format("{},{:.6f},{},{},{},{},{},{}\n", i, f.timestamp_ns * 1e-9, m.name,
                         m.steps[i].lost ? 1 : 0, m.steps[i].keyframe,
                         reg[i] ? fmt::format("{:.3f}", *reg[i]) : std::string(), rotation,
                         translation);
    }
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace probeless::eval

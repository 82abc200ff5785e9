// The running service on the sim, with its default config, mattes as well as `probeless eval
// occlusion --dataset sim` says its default method does (issue #19): the mean per-frame MSE of
// the service's mattes against the sim's truth within 10 % of the evaluator's for cvf on the
// same frames. The service exposes its matte and virtual depth to tests through
// PipelineOptions::keep_matte; the truth is the sim's clean depth against that virtual depth,
// as the evaluator's (lab/eval/sim_dataset.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include "app/pipeline/pipeline.hpp"
#include "drivers/rig_factory.hpp"
#include "lab/eval/occlusion_eval.hpp"
#include "support/pipeline_frames.hpp"

namespace probeless {
namespace {

// The evaluator's sim protocol with its defaults (tabletop rig, the arm and the near hand),
// shortened; the service's source is the same rig.
constexpr int kFrames = 60;
const std::string kSimOptions = "frames=" + std::to_string(kFrames);
// Every frame in order. When the light capture's first snapshot arrives depends on the
// threads (a few frames in, or not within the run), and until then the service draws its
// placeholder objects without the ground receiver; so the evaluator is given, frame by frame,
// the virtual depth the service drew (the tracked pose's), with the truth from it, and that
// pose for its stabiliser.
const std::string kServiceSource =
    "sim:realtime=0,trajectory=tabletop,start=1.5,near_occluder=1,edge_samples=4";

std::optional<double> frame_mse(const CompositeFrame& f) {
  double sum = 0;
  std::size_t n = 0;
  const ImageF& alpha = *f.alpha;
  const ImageF& virt = *f.virtual_depth;
  const DepthImage& clean = f.truth->clean_depth;
  for (int y = 0; y < alpha.height(); ++y)
    for (int x = 0; x < alpha.width(); ++x) {
      const float v = virt.at(x, y);
      const std::uint16_t real = clean.at(x, y);
      if (!(v > 0) || !real) continue;
      const double truth = static_cast<float>(real) >= v ? 1.0 : 0.0;
      const double d = alpha.at(x, y) - truth;
      sum += d * d;
      ++n;
    }
  if (!n) return std::nullopt;
  return sum / static_cast<double>(n);
}

std::size_t object_pixels(const ImageF& virtual_depth) {
  std::size_t n = 0;
  for (float v : virtual_depth.elements()) n += v > 0;
  return n;
}

TEST(MatteEvalAgreement, ServiceMatteMseMatchesTheEvaluatorsForCvf) {
  ServiceConfig config;  // the defaults: cvf, stabilised, tracking and light capture on
  config.source = kServiceSource;
  config.max_frames = kFrames;
  ASSERT_EQ(config.occlusion_method, "cvf");
  ASSERT_TRUE(config.occlusion_stabilise);
  PipelineOptions options;
  options.lossless = true;
  options.keep_matte = true;
  options.serve_http = false;
  Pipeline pipeline(config, open_rig(config.source), options);
  struct Scored {
    double mse;
    std::shared_ptr<const ImageF> virtual_depth;
    std::shared_ptr<const FrameTruth> truth;
    const DepthImage* clean = nullptr;
    std::optional<Pose> T_world_camera;  // the tracked pose the service stabilised with
  };
  std::map<std::uint64_t, Scored> service;  // by frame index (a NO SIGNAL repeat counts once)
  pipeline.start();
  testing::for_each_output_frame(pipeline, [&](const CompositeFrame& f) {
    if (!f.alpha || !f.truth || !f.virtual_depth) return;
    if (auto m = frame_mse(f))
      service[f.sequence] = {*m, f.virtual_depth, f.truth, &f.truth->clean_depth, f.T_world_camera};
  });
  pipeline.stop();
  EXPECT_FALSE(pipeline.fatal_error().has_value()) << pipeline.fatal_error().value_or("");

  // The evaluator's sim protocol on the same frames, with the service's virtual layer.
  eval::EvalOptions eo;
  eo.methods = {"cvf"};
  eo.stabilised = true;  // the service stabilises by default ([occlusion] stabilise)
  auto cases = eval::load_cases("sim:" + kSimOptions, eo);
  ASSERT_EQ(cases.size(), 1u);
  std::vector<eval::EvalFrame> kept;
  double service_sum = 0;
  std::size_t full_scene = 0;
  for (std::size_t i = 0; i < cases[0].frames.size(); ++i) {
    const auto it = service.find(i);
    if (it == service.end()) continue;
    eval::EvalFrame f = std::move(cases[0].frames[i]);
    const double drawn = double(object_pixels(f.virtual_depth_mm));
    full_scene += std::abs(double(object_pixels(*it->second.virtual_depth)) - drawn) < 0.05 * drawn;
    // The truth as the protocol makes it (sim_dataset.cpp), from the sim frame's clean depth:
    // visible where the real surface is not nearer.
    f.virtual_depth_mm = *it->second.virtual_depth;
    // The stabiliser re-projects the previous matte with the camera's motion: the service's
    // is the tracked one, so the evaluator is given that rather than the sim's true pose.
    f.T_world_camera = it->second.T_world_camera;
    f.truth = ImageF(f.virtual_depth_mm.width(), f.virtual_depth_mm.height());
    f.mask = ImageGray8(f.truth.width(), f.truth.height());
    for (int y = 0; y < f.truth.height(); ++y)
      for (int x = 0; x < f.truth.width(); ++x) {
        const float v = f.virtual_depth_mm.at(x, y);
        const std::uint16_t real = it->second.clean->at(x, y);
        if (!(v > 0) || !real) continue;
        f.mask.at(x, y) = 255;
        f.truth.at(x, y) = static_cast<float>(real) >= v ? 1.0F : 0.0F;
      }
    f.contact_band = {};
    f.near_band = {};
    kept.push_back(std::move(f));
    service_sum += it->second.mse;
  }
  std::cout << full_scene << " of " << kept.size()
            << " frames with the ground receiver (after the light capture's first snapshot)\n";
  ASSERT_GE(kept.size(), std::size_t(kFrames * 3 / 4)) << "the service skipped frames";
  cases[0].frames = std::move(kept);
  ComputeContext ctx;
  const eval::EvalReport report = eval::evaluate(ctx, cases, eo);
  const double eval_cvf = report.mean.at("cvf").mse;
  const double eval_stab = report.mean.at(eval::stabilised_name("cvf")).mse;
  const double service_mse = service_sum / double(cases[0].frames.size());
  std::cout << "matte MSE x1e3 over " << cases[0].frames.size() << " frames: service "
            << service_mse * 1e3 << "; eval cvf " << eval_cvf * 1e3 << ", cvf+stab "
            << eval_stab * 1e3 << "\n";
  RecordProperty("service_mse", std::to_string(service_mse));
  RecordProperty("eval_cvf_stab_mse", std::to_string(eval_stab));
  EXPECT_NEAR(service_mse, eval_stab, 0.1 * eval_stab);
}

}  // namespace
}  // namespace probeless

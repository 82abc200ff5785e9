#pragma once
// The sim protocol's metrics beside matte_metrics.hpp (docs/occlusion.md "Sim protocol"):
// temporal noise over short windows (a moving camera), and the composite error at fractional
// matte pixels through the service's compositor.
#include <optional>
#include <vector>

#include "core/image.hpp"
#include "kernels/composite/compositor.hpp"
#include "kernels/occlusion/foreground/foreground_estimate.hpp"
#include "lab/eval/eval_case.hpp"

namespace probeless::eval {

// temporal_noise() over consecutive windows of `window` frames (a trailing shorter window is
// dropped) at the pixels whose truth is the same in every frame of the window, averaged over
// the windows that have a value; window <= 1 or >= the frame count: temporal_noise() over
// all frames (the static-scene definition, where the truth never changes).
std::optional<double> windowed_temporal_noise(const std::vector<ImageF>& alphas,
                                              const std::vector<ImageF>& truths,
                                              const std::vector<ImageGray8>& masks, int window);

// Mean over the channels and the evaluated pixels whose alpha is fractional (0.01 < alpha <
// 0.99) of (composite - true composite)^2, colours / 255. composite = the service's
// compositor (kernels/composite) on the observed colour; true composite = truth x virtual +
// (1 - truth) x true foreground, rounded as the compositor rounds. nullopt without pixels.
std::optional<double> fractional_composite_error(const EvalFrame& frame, const ImageF& alpha,
                                                 const ImageRGB8& composite);

// A frame's composite error (fractional_composite_error) both ways; -1 where it has none.
struct CompositeErrors {
  double estimated = -1;  // the service's composite stage: ForegroundEstimate, then Compositor
  double observed = -1;   // Compositor on the observed colour (no foreground estimate)
};

// Runs the service's compositing for a frame and scores it (above), with and without the
// foreground colour estimate at fractional matte pixels (issue #19 item 5).
class SimComposite {
 public:
  explicit SimComposite(ComputeContext& ctx) : ctx_(ctx), foreground_(ctx), compositor_(ctx) {}
  // Both -1 when the frame has no virtual colour (not the sim protocol) or no fractional pixel.
  // host_alpha: `alpha` as the caller already downloaded it.
  CompositeErrors error(const EvalFrame& frame, const DeviceImageRGB8& colour,
                        const DeviceImageF& virtual_depth_mm, const DeviceImageF& alpha,
                        const ImageF& host_alpha);

 private:
  double score(const EvalFrame& frame, const DeviceImageF& alpha, const ImageF& host_alpha,
               const DeviceImageRGB8& real);

  ComputeContext& ctx_;
  occlusion::ForegroundEstimate foreground_;
  Compositor compositor_;
  DeviceImageRGBA8 virtual_colour_;
  DeviceImageRGB8 estimated_, out_;
};

}  // namespace probeless::eval

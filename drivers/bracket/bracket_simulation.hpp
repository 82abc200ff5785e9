#pragma once
// A simulated linear camera that brackets a real HDR image with the BracketSequencer, the
// hat-weighted merge of one cycle, and the evaluation of `probeless eval hdr`
// (docs/bracketing.md "Camera simulation and merge").
#include <cstdint>
#include <random>
#include <span>
#include <string>

#include "core/exposure.hpp"
#include "core/image.hpp"
#include "drivers/bracket/bracket_sequencer.hpp"

namespace probeless {

// value = clamp(round(black + s + n_shot + n_read), 0, 2^bits - 1), s = radiance * E * k in DN,
// n_shot ~ N(0, s * g / e_per_dn) (Poisson electrons, Gaussian approximation, g = analogue
// gain), n_read ~ N(0, read_noise_dn^2) referred to the output.
struct SimulatedCameraModel {
  int bits = 8;
  std::uint16_t black_level = 16;
  double full_well_e = 10000.0;  // electrons at full scale at 0 dB
  double read_noise_dn = 0.3;
  double scale = 1.0;                              // k: DN per unit radiance per unit E
  static SimulatedCameraModel for_bits(int bits);  // the defaults docs/bracketing.md lists
  int full_scale() const { return (1 << bits) - 1; }
};

ImageRGB16 simulate_capture(const ImageRGBF& radiance, const Exposure& exposure,
                            const SimulatedCameraModel& camera, std::mt19937_64& rng);

struct BracketFrame {
  ExposureStamp stamp;
  ImageRGB16 raw;
};

// How merge_bracket weighs the samples of one pixel and channel.
enum class MergeWeights {
  // The hat S(x) = x below 0.5, 1 - x above, x the normalised signal (the thesis's best
  // score, ch. 5): knows nothing of the sensor.
  Hat,
  // Inverse variance of each sample's radiance estimate under the camera's noise model
  // (Granados et al. 2010, "Optimal HDR reconstruction with linear digital cameras"):
  // w = (E k)^2 / (s g_e + sigma_read^2 + 1/12), s the signal in DN predicted from a first,
  // hat-weighted estimate (a sample's own value would favour samples that read low), g_e the
  // DN per electron at the frame's gain; 1/12 is the rounding's variance.
  NoiseOptimal,
};

// Per channel, the weighted mean of (value - black) / E over the samples that are neither
// saturated nor zero, divided by k. Channels with no such sample are 0 and their pixel is
// cleared in `measured` (if given).
ImageRGBF merge_bracket(std::span<const BracketFrame> frames, const SimulatedCameraModel& camera,
                        ImageGray8* measured = nullptr, MergeWeights weights = MergeWeights::Hat);

struct HdrEvalOptions {
  int bits = 8;
  int cycles = 16;  // frames simulated = 4 * cycles
  // Merge the frames of the last this many cycles. 6 cycles (0.48 s at 50 fps) stand for the
  // averaging the keyframe texels do over time (thesis ch. 5-6); one cycle alone leaves the
  // median at 1.3-1.8 % with a 10 000 e- sensor (docs/bracketing.md "Results").
  int merge_cycles = 6;
  MergeWeights weights = MergeWeights::NoiseOptimal;
  std::uint64_t seed = 1;
  double full_well_e = 0;                 // 0: the model's default (SimulatedCameraModel::for_bits)
  double read_noise_dn = -1;              // < 0: the model's default
  double median_fraction_of_full = 0.18;  // k puts the median luminance here at the start E
  BracketConfig sequencer;
};

struct HdrEvalReport {
  std::string image;
  int bits = 8;
  int merge_cycles = 1;  // the options' window and weights, echoed
  MergeWeights weights = MergeWeights::NoiseOptimal;
  double median_rel_error = 0;
  double p95_rel_error = 0;
  double measurable_fraction = 0;
  int settle_cycles = 0;  // first cycle from which L, M, H no longer changed
  bool settled = false;   // they did not change in the last quarter of the run
  int low_stop = 0, medium_stop = 0, high_stop = 0;  // final, relative to the start E
  double low_exposure = 0, medium_exposure = 0, high_exposure = 0;
  double scene_range = 0;  // max / min non-zero luminance of the image
};

// Brackets `radiance` with the sequencer for opts.cycles cycles, merges the last cycle and
// compares with the image. The relative error of a pixel is |est - true| / |true| (RGB norms).
HdrEvalReport evaluate_bracketing(const ImageRGBF& radiance, const HdrEvalOptions& opts);

}  // namespace probeless

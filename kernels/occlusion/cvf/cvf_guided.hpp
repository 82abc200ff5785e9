#pragma once
// The guided filter as one row-streaming kernel (cvf_guided.cl): coefficients, their means and
// the output in a single launch, reading its input straight from CVF's buffers (the cost of
// each pixel for the wide filter, the threshold of the wide filter for the feather filter) so
// that no intermediate image goes through global memory. guided_filter_reference.hpp is the
// CPU twin; tests/kernels/cvf compares them.
#include <string>

#include "kernels/runtime/compute_context.hpp"

namespace probeless::occlusion {

class StripGuidedFilter {
 public:
  enum class Input {
    Packed = 0,      // float4 (r, g, b, p) per pixel
    CvfCost = 1,     // CVF's cost from colour, categories, depths and histograms
    CvfFeather = 2,  // CVF's threshold of the wide filter's mean coefficients
  };
  enum class Output {
    MeanCoefficients = 0,    // window means of (a, b), float4 per pixel
    VisibilityFromCost = 1,  // virtual > 0 ? clamp(1 - q) : 0
    Raw = 3,                 // q
  };
  // Largest radius: the zero padding of the scratch rows covers 16 + r + 1 columns.
  static constexpr int kMaxRadius = 16;
  // Zero columns on each side of a scratch row (PAD in cvf_vector.cl), and a row's floats.
  static constexpr std::size_t kScratchPad = 48;
  // Replicated edge columns on each side of the mean coefficients (MEAN_PAD in cvf_guided.cl).
  static constexpr int kMeanPad = 16;
  // Strips of rows for h rows on `units` compute units, when each strip also walks
  // `warmup_rows` rows outside it: a multiple of the units (so an idle machine splits them
  // evenly), as many as keep the warm-up within 1/4 of a strip, at most 4 per unit (more
  // strips balance a loaded machine better; fewer waste less on warm-up).
  static int strip_count(int h, int warmup_rows, int units);
  static std::size_t scratch_row(int width) {
    return kScratchPad + (static_cast<std::size_t>(width) + 15) / 16 * 16 + kScratchPad;
  }

  // `extra_options`: -DBINS / -DSUBSAMPLE for the CVF inputs. With `trace`, every pixel's input
  // (r, g, b, p) is also written to the trace buffer (tests).
  StripGuidedFilter(ComputeContext& ctx, int radius, float eps, Input input, Output output,
                    const std::string& extra_options = {}, bool trace = false);
  int radius() const { return radius_; }

  // Arguments from index kFirstArg on are the input's and output's (cvf_guided.cl,
  // KERNEL_INPUT_ARGS and OUTPUT_ARGS, then the trace buffer); run() sets the ones before
  // (sizes, eps, scratch, the active rows) and enqueues over w x h, one work-item per strip of
  // rows.
  ::cl::Kernel& kernel() { return kernel_; }
  static constexpr cl_uint kFirstArg = 9;

  // Computes only the output pixels with an object pixel within `reach` full-resolution pixels
  // (object_cols: per full-resolution row y < n_rows the object's columns [begin, end) at
  // [2 y], [2 y + 1]; output row yo covers full rows yo scale .. yo scale + scale - 1), and
  // writes CVF's constant output elsewhere (cvf_guided.cl, object_columns()). reach < 0 (the
  // default): every pixel.
  void set_active_rows(const ::cl::Buffer& object_cols, int n_rows, int scale, int reach);
  void run(int w, int h);

 private:
  ComputeContext& ctx_;
  int radius_;
  float eps_;
  ::cl::Kernel kernel_;
  ::cl::Buffer scratch_;
  std::size_t scratch_bytes_ = 0;
  ::cl::Buffer row_object_;
  int n_rows_ = 0, row_scale_ = 1, reach_ = -1;
};

}  // namespace probeless::occlusion
